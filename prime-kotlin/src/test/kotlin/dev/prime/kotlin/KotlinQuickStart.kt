package dev.prime.kotlin

import dev.prime.liberty.LibertyCore
import kotlinx.coroutines.delay
import kotlinx.coroutines.flow.flowOf
import kotlinx.coroutines.flow.take
import kotlinx.coroutines.flow.toList
import kotlinx.coroutines.withTimeoutOrNull
import java.io.PrintStream

/** The README's Kotlin section, compiled: the code between the markers is shown there verbatim. */
internal object KotlinQuickStart {
    suspend fun run(out: PrintStream) {
        // kotlin-quick-start:begin
        LibertyCore().use { core -> // or RadiantCore(), OptimusCore(): nothing else changes
            // A flow feeds a source while the core runs: collected from start() to close().
            val thermometer = core.source("thermometer", flowOf(21.5, 22.0, 23.5))
            val reports = thermometer.then(core.chain("format") { c: Double -> "${c * 9 / 5 + 32} F" })

            // A block may suspend; calling a chain's block suspends and honours cancellation.
            val slow = core.chain("slow", suspendingBlock { c: Double -> delay(10_000); c }).toBlock()
            val convert = core.chain("convert") { c: Double -> c * 9 / 5 + 32 }.toBlock()
            core.start()

            out.println(reports.asFlow().take(3).toList()) // [70.7 F, 71.6 F, 74.3 F]
            out.println(convert.processSuspending(100.0)) // 212.0
            out.println(withTimeoutOrNull(50) { slow.processSuspending(1.0) }) // null, after 50 ms
        } // the source's flow completes here, the thermometer's collection is cancelled
        // kotlin-quick-start:end
    }
}

package dev.prime.optimus

import java.util.concurrent.atomic.AtomicInteger
import kotlin.system.exitProcess

/**
 * The worker JVM of the competing-consumer tests: `ConsumerWorkerMain REDIS_URL CORE_NAME MODE
 * BLOCK_MS` declares [CompetingTopology], hosts its service with hosting MODE (`ORDERED`,
 * `UNORDERED`), starts, and prints `READY <instance id>`. On a line `STOP` it prints
 * `PROCESSED n` (the values its block ran on) and ends. A failing start prints `FAILED <message>`.
 */
object ConsumerWorkerMain {
    @JvmStatic
    fun main(args: Array<String>) {
        if (args.size != 4) {
            System.err.println("usage: ConsumerWorkerMain REDIS_URL CORE_NAME ORDERED|UNORDERED BLOCK_MS")
            exitProcess(2)
        }
        val processed = AtomicInteger()
        CompetingTopology.core(args[0], args[1], Hosting.valueOf(args[2])).use { core ->
            CompetingTopology.declare(core, args[3].toLong()) { processed.incrementAndGet() }
            try {
                core.start()
            } catch (e: IllegalStateException) {
                println("FAILED ${e.message}")
                System.out.flush()
                exitProcess(1)
            }
            println("READY ${core.instanceId}")
            System.out.flush()
            generateSequence { readlnOrNull() }.firstOrNull { it.trim() == "STOP" }
            println("PROCESSED ${processed.get()}")
            System.out.flush()
        }
    }
}

package dev.prime.optimus

import dev.prime.ChainFailedException
import dev.prime.EventBlock
import kotlinx.coroutines.flow.take
import kotlinx.coroutines.flow.toList
import kotlinx.coroutines.async
import kotlinx.coroutines.runBlocking
import kotlinx.coroutines.withTimeout
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Test

/** The Kotlin additions: suspending calls and sources as flows. */
class CoroutinesTest {

    @Test
    fun suspendingCallsAndAFlowOfASource() = runBlocking {
        TestRedis.core().use { core ->
            val events = EventBlock<Int>()
            val squares = core.source(events).then(core.chain("square") { x: Int -> x * x })
            val negate = core.chain("negate") { x: Int -> if (x == 0) throw IllegalArgumentException("zero") else -x }.toBlock()
            core.start()
            val collected = async { withTimeout(20_000) { squares.asFlow().take(3).toList() } }
            assertEquals(-7, negate.processSuspending(7))
            val failure = assertThrows(ChainFailedException::class.java) { runBlocking { negate.processSuspending(0) } }
            assertEquals("negate", failure.chainName())
            (1..3).forEach(events::publish)
            assertEquals(listOf(1, 4, 9), collected.await())
        }
    }
}

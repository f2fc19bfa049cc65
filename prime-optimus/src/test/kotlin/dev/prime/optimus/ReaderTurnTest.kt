package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.lang.management.ManagementFactory
import java.time.Duration
import java.util.concurrent.CompletableFuture
import java.util.concurrent.TimeUnit

/**
 * A poll of a reader whose turn another call holds for a round trip waits for that call in the
 * lock's queue: it does not spin, also when its thread is interrupted (poll throws no
 * InterruptedException, so the interrupt is kept for the caller, not waited on).
 */
class ReaderTurnTest {

    @Test
    fun anInterruptedPollWaitsForAnotherCallsRoundTripWithoutSpinningAndKeepsTheInterrupt() {
        FaultProxy(TestRedis.url).use { proxy ->
            val config = CoreConfig.builder().name("turn-${System.nanoTime()}").build()
            OptimusCore.builder().config(config).redis(proxy.url).build().use { core ->
                val events = EventBlock<Int>()
                val reader = core.source(events).reader() as OptimusReader<Int>
                core.start()
                events.publish(1)
                assertEquals(1, reader.take(PATIENCE).orElseThrow())
                proxy.freeze()
                try {
                    // a drain holds the turn while Redis does not answer (at most about a second)
                    val drain = CompletableFuture.runAsync { runCatching { reader.drain() } }
                    val until = System.nanoTime() + PATIENCE.toNanos()
                    while (!reader.isTurnHeld && !drain.isDone && System.nanoTime() < until) Thread.onSpinWait()
                    assertTrue(reader.isTurnHeld, "the drain holds the reader's turn")
                    val poll = CompletableFuture.supplyAsync {
                        val threads = ManagementFactory.getThreadMXBean()
                        Thread.currentThread().interrupt()
                        val cpu = threads.currentThreadCpuTime
                        val outcome = runCatching { reader.poll() }.exceptionOrNull()?.javaClass?.simpleName ?: "returned"
                        val spent = Duration.ofNanos(threads.currentThreadCpuTime - cpu)
                        Triple(outcome, spent, Thread.interrupted())
                    }
                    val (outcome, spent, interruptKept) = poll.get(PATIENCE.toSeconds(), TimeUnit.SECONDS)
                    drain.get(PATIENCE.toSeconds(), TimeUnit.SECONDS)
                    println("an interrupted poll behind a drain on a frozen link: $outcome, CPU ${spent.toMillis()} ms")
                    assertEquals("RedisUnavailableException", outcome, "the poll fails at once on the frozen link")
                    assertTrue(interruptKept, "the poll leaves its thread's interrupt set")
                    assertTrue(spent < CPU_BOUND, "the poll waited for the drain without spinning: CPU $spent")
                } finally {
                    proxy.thaw()
                }
            }
        }
    }

    private companion object {
        val PATIENCE: Duration = Duration.ofSeconds(20)
        val CPU_BOUND: Duration = Duration.ofMillis(150)
    }
}

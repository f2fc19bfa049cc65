package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration
import java.util.Optional
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * A close that interrupts a service's block waiting on a latch (at once, not after
 * `shutdownTimeout`) loses no value and stores nothing the interrupted block returned: the value
 * stays in the service's processing list, and the next core of the topology runs it.
 */
class InterruptedCloseRedeliveryTest {

    @Test
    fun aValueWhoseBlockACloseInterruptedIsRunAgainByTheNextCore() {
        val config = CoreConfig.builder()
            .name("interrupted-close-" + java.lang.Long.toString(System.nanoTime(), 36))
            .shutdownTimeout(PATIENCE.multipliedBy(3))
            .build()
        val inside = CountDownLatch(1)
        val never = CountDownLatch(1)
        val sawInterrupt = CountDownLatch(1)
        try {
            TestRedis.core(config).use { first ->
                val events = EventBlock<Int>()
                first.source("events", events)
                    .then(first.chain("waiting") { x: Int ->
                        inside.countDown()
                        try {
                            never.await(PATIENCE_SECONDS * 4, TimeUnit.SECONDS)
                        } catch (_: InterruptedException) {
                            sawInterrupt.countDown()
                            Thread.currentThread().interrupt()
                        }
                        -x // never stored: its connections are closed when the interrupt comes
                    })
                    .reader()
                first.start()
                events.publish(1)
                assertTrue(inside.await(PATIENCE_SECONDS, TimeUnit.SECONDS), "the block runs")
                val began = System.nanoTime()
                first.close()
                val took = Duration.ofNanos(System.nanoTime() - began)
                assertTrue(took < PATIENCE, "close() took $took, shutdownTimeout ${config.shutdownTimeout()}")
                assertTrue(sawInterrupt.await(PATIENCE_SECONDS, TimeUnit.SECONDS), "the block saw the interrupt")
            }
        } finally {
            never.countDown()
        }
        TestRedis.core(config).use { second ->
            val events = EventBlock<Int>()
            val reader = second.source("events", events)
                .then(second.chain("waiting") { x: Int -> x * 10 })
                .reader()
            second.start()
            assertEquals(Optional.of(10), reader.take(PATIENCE), "the value the close interrupted is run again")
            assertEquals(Optional.empty<Int>(), reader.take(Duration.ofMillis(300)), "and nothing else came out")
        }
    }

    private companion object {
        const val PATIENCE_SECONDS = 20L
        val PATIENCE: Duration = Duration.ofSeconds(PATIENCE_SECONDS)
    }
}

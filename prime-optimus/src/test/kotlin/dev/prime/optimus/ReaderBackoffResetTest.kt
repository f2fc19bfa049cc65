package dev.prime.optimus

import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicLong

/**
 * A reader's back-off between attempts to reach Redis starts again from its shortest wait after
 * any round trip that succeeded, not only after a blocking wait: a reader whose takes always found
 * values after a long outage, then met a short one, waited the longest back-off (a second) before
 * it tried again, and recovered about a second after Redis was back.
 */
class ReaderBackoffResetTest {

    @Test
    fun aReaderThatFoundValuesAfterALongOutageRecoversFromAShortOneWithinItsShortestWaits() {
        withProxiedReaderCore("backoff-reset") { publisher, numbers, proxy, readerCore ->
            val reader = readerCore.source("numbers", EventBlock<Int>()).reader()
            readerCore.start()
            // a long outage: the reader's back-off grows to its longest wait
            proxy.refuse()
            assertThrows(RedisUnavailableException::class.java) { reader.take(Duration.ofMillis(2500)) }
            proxy.restore()
            // Redis is back; every take finds a value at once (no blocking wait)
            for (n in 1..3) publisher.publishAll(numbers, listOf(n))
            for (n in 1..3) assertEquals(n, reader.take(PATIENCE).orElseThrow())
            // a short outage: Redis is back 100 ms after it went
            proxy.refuse()
            publisher.publishAll(numbers, listOf(4))
            val restoredAt = AtomicLong()
            val stop = CountDownLatch(1)
            val restorer = Thread {
                stop.await(OUTAGE_MS, TimeUnit.MILLISECONDS) // the outage's length, not a wait for an event
                restoredAt.set(System.nanoTime())
                proxy.restore()
            }.apply { isDaemon = true }
            restorer.start()
            try {
                assertEquals(4, reader.take(PATIENCE).orElseThrow())
                val recoveredMs = (System.nanoTime() - restoredAt.get()) / 1_000_000
                println("ReaderBackoffResetTest: the reader got its value $recoveredMs ms after Redis was back")
                assertTrue(recoveredMs < RECOVERY_BOUND_MS, "the reader recovered $recoveredMs ms after Redis was back")
            } finally {
                stop.countDown()
                restorer.join(PATIENCE.toMillis())
            }
        }
    }

    private companion object {
        val PATIENCE: Duration = Duration.ofSeconds(20)
        const val OUTAGE_MS = 100L

        /** Well under the longest back-off (1 s); the shortest waits (20, 40, 80, 160 ms) cover the outage. */
        const val RECOVERY_BOUND_MS = 600L
    }
}

package dev.prime.optimus

import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import java.time.Duration

/**
 * A publish whose wait between attempts to reach Redis meets its thread's interrupt flag ends
 * with a [PrimeException] that says so, the flag kept, on an open core: never in silence (the
 * value would be lost without a word) and never as [CoreClosedException] (the core is open).
 */
class InterruptedPublishTest {

    @Test
    fun aPublishInterruptedWhileRedisIsUnreachableFailsSayingSoAndKeepsTheFlag() {
        withProxiedReaderCore("interrupted-publish") { _, numbers, proxy, core ->
            val events = EventBlock<Int>()
            core.source("numbers", events)
            core.start()
            val reader = numbers.reader() // the same source, read through the publisher's core
            proxy.refuse()
            assertInterruptedInOutage("a publish", "numbers") { events.publish(1) }
            proxy.restore()
            events.publish(2)
            assertEquals(2, reader.take(PATIENCE).orElseThrow(), "the source publishes on")
        }
    }

    /** Opening a reader also waits for Redis in an outage: interrupted there, the same kind of failure. */
    @Test
    fun openingAReaderInterruptedWhileRedisIsUnreachableFailsSayingSoAndKeepsTheFlag() {
        withProxiedReaderCore("interrupted-reader") { publisher, published, proxy, core ->
            val numbers = core.source("numbers", EventBlock<Int>())
            core.start()
            proxy.refuse()
            assertInterruptedInOutage("opening a reader", "numbers") { numbers.reader() }
            proxy.restore()
            numbers.reader().use { reader ->
                publisher.publishAll(published, listOf(3))
                assertEquals(3, reader.take(PATIENCE).orElseThrow(), "a reader opened once Redis is back reads")
            }
        }
    }

    /** A reader's missed() reads its count in Redis: interrupted while it waits for Redis, the same kind of failure. */
    @Test
    fun aReadersMissedCountInterruptedWhileRedisIsUnreachableFailsSayingSoAndKeepsTheFlag() {
        withProxiedReaderCore("interrupted-missed") { _, _, proxy, core ->
            val numbers = core.source("numbers", EventBlock<Int>())
            core.start()
            numbers.reader().use { reader ->
                proxy.refuse()
                assertInterruptedInOutage("a reader's missed()", "numbers") { reader.missed() }
                proxy.restore()
                assertEquals(0L, reader.missed(), "the reader works on once Redis is back")
            }
        }
    }

    private companion object {
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

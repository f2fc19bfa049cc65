package dev.prime.optimus

import dev.prime.EventBlock
import dev.prime.PrimeException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import java.time.Duration
import java.util.Optional

/**
 * A conflated reader's take takes a value, then drains what came after it to return the newest.
 * Over a link whose round trip is longer than a drain waits for Redis (a reply a second late, as a
 * slow or congested link: a take waits for it, a drain gives up after 750 ms), the drain fails
 * after the take got its value: the take returns that value, once, rather than throw and lose it
 * (the wrapped reader had handed it out, so no later read returned it: a take then waited for a
 * newer value, for ever if none was published).
 */
class ConflatedReaderSlowLinkTest {

    @Test
    fun aConflatedTakeReturnsTheValueItTookWhenItsDrainForNewerOnesFails() {
        withProxiedReaderCore("conflated-slow") { publisher, numbers, proxy, readerCore ->
            val latest = readerCore.source("numbers", EventBlock<Int>()).conflatedReader()
            readerCore.start()
            publisher.publishAll(numbers, listOf(1))
            assertEquals(1, latest.take(PATIENCE).orElseThrow(), "warm: the reader is connected and reads")

            proxy.replyDelayNanos = SLOW_REPLY.toNanos()
            publisher.publishAll(numbers, listOf(2))
            val untimed = outcome { latest.take() }
            publisher.publishAll(numbers, listOf(3))
            val timed = outcome { latest.take(PATIENCE).orElse(null) }
            proxy.replyDelayNanos = 0
            val after = outcome { latest.take(Duration.ofSeconds(2)).orElse(null) }

            assertEquals(
                listOf("value 2", "value 3", "value null"),
                listOf(untimed, timed, after),
                "take() and take(timeout) returned the value each took, and a take after them found nothing newer",
            )
            assertEquals(Optional.empty<Int>(), latest.poll(), "nothing newer: each value came once")
            publisher.publishAll(numbers, listOf(4))
            assertEquals(4, latest.take(PATIENCE).orElseThrow(), "the reader goes on")
        }
    }

    private fun outcome(read: () -> Int?): String = try {
        "value ${read()}"
    } catch (e: PrimeException) {
        "${e.javaClass.simpleName}: ${e.message}"
    }

    private companion object {
        val PATIENCE: Duration = Duration.ofSeconds(20)

        /** Longer than a drain waits for Redis (500 ms plus 250 ms of socket grace), shorter than a take's 10 s. */
        val SLOW_REPLY: Duration = Duration.ofSeconds(1)
    }
}

package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration
import java.util.Optional

/**
 * A reader over a link of half a second's round trip (a robot on Wi-Fi far from its access point):
 * a [LatencyProxy] delays every byte [ONE_WAY_MS] each way. A timed take on its open connection
 * keeps the Reader contract: it returns empty when no value came (Redis answered, slowly), within
 * its timeout plus about a second, even when the timeout is shorter than a round trip; and it
 * loses and duplicates nothing.
 */
class HighLatencyReaderTest {

    @Test
    fun aTimedTakeOverAHalfSecondRoundTripReturnsEmptyInTimeAndLosesNothing() {
        LatencyProxy(TestRedis.url, Duration.ofMillis(ONE_WAY_MS).toNanos()).use { proxy ->
            val config = CoreConfig.builder().name("high-latency-${System.nanoTime()}").build()
            OptimusCore.builder().config(config).redis(proxy.url).build().use { core ->
                val events = EventBlock<Int>()
                val reader = core.source(events).reader()
                core.start()
                events.publish(1)
                // the reader's first take opens its connection (a few round trips): not timed
                assertEquals(1, reader.take(PATIENCE).orElseThrow())
                val took = ArrayList<String>()
                for (timeout in TIMEOUTS) {
                    val started = System.nanoTime()
                    val got = reader.take(timeout)
                    val spent = Duration.ofNanos(System.nanoTime() - started)
                    took += "take(${timeout.toMillis()} ms): $got after ${spent.toMillis()} ms"
                    assertEquals(Optional.empty<Int>(), got, "nothing was published: $took")
                    assertTrue(spent >= timeout, "returned before its timeout: $took")
                    assertTrue(spent <= timeout.plus(BOUND), "more than the timeout plus $BOUND: $took")
                }
                println("[high latency] round trip ${2 * ONE_WAY_MS} ms: $took")
                events.publish(2)
                events.publish(3)
                assertEquals(2, reader.take(PATIENCE).orElseThrow())
                assertEquals(3, reader.take(Duration.ofSeconds(1)).orElseThrow())
                assertEquals(Optional.empty<Int>(), reader.take(Duration.ofMillis(100)), "no value twice")
            }
        }
    }

    private companion object {
        const val ONE_WAY_MS = 250L
        val TIMEOUTS: List<Duration> = listOf(100L, 1000L, 1500L, 100L).map(Duration::ofMillis)

        /** The Reader contract's bound past a timeout ("plus about a second"). */
        val BOUND: Duration = Duration.ofSeconds(1)
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

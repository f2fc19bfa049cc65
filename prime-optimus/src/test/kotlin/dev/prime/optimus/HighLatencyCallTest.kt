package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.PrimeException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.assertThrows
import java.time.Duration
import java.util.Optional
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * Calls and publishes over a link of half a second's round trip (a robot on Wi-Fi far from its
 * access point): the caller's core reaches Redis through a [LatencyProxy] that delays every byte
 * [ONE_WAY_MS] each way; the services run in a core on the plain link. A call keeps its
 * `callTimeout` promise: a service that answers is heard (a thread's first call too, which first
 * records its reply list and connects), and a service that never answers ends the call after the
 * timeout, within about a second, with the timeout's [PrimeException], not a
 * [RedisUnavailableException] (Redis answered, slowly), and without losing the connection. A
 * publish within its `publishTimeout` stores each value once.
 */
class HighLatencyCallTest {

    @Test
    fun aCallOverAHalfSecondRoundTripKeepsItsTimeout() {
        val release = CountDownLatch(1)
        val config = CoreConfig.builder().name("high-latency-call-${System.nanoTime()}").build()
        val host = OptimusCore.builder().config(config).redis(TestRedis.url).hosts("hl-quick", "hl-never").build()
        try {
            host.chain("hl-quick") { x: Int -> x + 1 }.toBlock()
            host.chain("hl-never") { x: Int -> release.await(1, TimeUnit.MINUTES); x }.toBlock()
            val values = host.source("hl-values", EventBlock<Int>()).reader()
            host.start()
            LatencyProxy(TestRedis.url, Duration.ofMillis(ONE_WAY_MS).toNanos()).use { proxy ->
                OptimusCore.builder().config(config).redis(proxy.url).hosts()
                    .callTimeout(TIMEOUT).publishTimeout(TIMEOUT).build().use { caller ->
                        val quick = caller.chain("hl-quick") { x: Int -> x + 1 }.toBlock()
                        val never = caller.chain("hl-never") { x: Int -> x }.toBlock()
                        val events = EventBlock<Int>()
                        val source = caller.source("hl-values", events)
                        caller.start()
                        val took = ArrayList<String>()

                        // a thread's first call records its reply list and connects (three round trips) before its own
                        val first = timed { quick.process(1) }
                        took += "first call: ${first.toMillis()} ms"
                        assertTrue(first <= TIMEOUT.plus(BOUND), "a first call answered within the timeout plus $BOUND: $took")
                        for (x in 2..3) {
                            val spent = timed { assertEquals(x + 1, quick.process(x)) }
                            took += "call: ${spent.toMillis()} ms"
                            assertTrue(spent < TIMEOUT, "a call on the open connection within its timeout: $took")
                        }
                        repeat(2) {
                            val started = System.nanoTime()
                            val e = assertThrows<Exception> { never.process(it) }
                            val spent = Duration.ofNanos(System.nanoTime() - started)
                            took += "unanswered call: ${e.javaClass.simpleName} after ${spent.toMillis()} ms"
                            assertTrue(
                                e is PrimeException && e !is RedisUnavailableException && "did not reply within" in e.message!!,
                                "Redis answered (slowly): the call ends with the timeout's PrimeException, not $e; $took",
                            )
                            assertTrue(spent >= TIMEOUT, "ended before its timeout: $took")
                            assertTrue(spent <= TIMEOUT.plus(BOUND), "more than the timeout plus $BOUND: $took")
                            // the connection stayed open: the next call needs no reconnect (two round trips more)
                            val next = timed { assertEquals(11, quick.process(10)) }
                            took += "next call: ${next.toMillis()} ms"
                            assertTrue(next < OPEN_CALL, "the call after it on the open connection within $OPEN_CALL: $took")
                        }
                        val publishes = listOf(timed { events.publish(1) }, timed { caller.publishAll(source, listOf(2, 3)) })
                        took += "publish, publishAll: ${publishes.map { it.toMillis() }} ms"
                        println("[high latency] round trip ${2 * ONE_WAY_MS} ms, callTimeout $TIMEOUT: $took")
                        assertTrue(publishes.all { it <= TIMEOUT }, "publishes within their timeout: $took")
                        assertEquals(listOf(1, 2, 3), (1..3).map { values.take(PATIENCE).orElseThrow() })
                        assertEquals(Optional.empty<Int>(), values.take(Duration.ofMillis(200)), "no value twice")
                    }
            }
        } finally {
            release.countDown()
            host.close()
        }
    }

    private fun timed(action: () -> Unit): Duration {
        val started = System.nanoTime()
        action()
        return Duration.ofNanos(System.nanoTime() - started)
    }

    private companion object {
        const val ONE_WAY_MS = 250L
        val TIMEOUT: Duration = Duration.ofSeconds(2)

        /** The promise's bound past a call timeout ("within about a second"). */
        val BOUND: Duration = Duration.ofSeconds(1)

        /** A call on an open connection takes one round trip; a reconnect two more. */
        val OPEN_CALL: Duration = Duration.ofMillis(3 * ONE_WAY_MS * 2 - 100)
        val PATIENCE: Duration = Duration.ofSeconds(10)
    }
}

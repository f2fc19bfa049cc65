package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.Reader
import dev.prime.conformance.CapturedStderr
import dev.prime.conformance.ConformanceBase
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * Optimus over a slow network link: every reply of Redis comes [DELAY_MS] late (a round trip of a
 * robot on Wi-Fi, or across a data centre), with the default settings (5 s lease, heartbeat every
 * third of it, 60 s call timeout). Two cores of one topology: one hosts the services, the other
 * publishes, reads and calls. Everything arrives once and in order, every call is answered, no
 * lease lapses and no process is taken for dead, and each close stays within its timeout and
 * leaves nothing behind. `-Dprime.slowLink.delayMs=100` runs it at another delay.
 */
class SlowLinkTest {

    @Test
    fun aTopologyOverALinkOfTensOfMillisecondsKeepsItsPromises() {
        val name = "slow-link"
        val config = CoreConfig.builder().name(name).build()
        val delay = Duration.ofMillis(DELAY_MS)
        val err = CapturedStderr()
        err.use { FaultProxy(TestRedis.url, delay.toNanos()).use { proxy ->
            val began = System.nanoTime()
            val host = OptimusCore.builder().config(config).redis(proxy.url).hosts("slow-double", "slow-square").build()
            val other = OptimusCore.builder().config(config).redis(proxy.url).hosts().build()
            val closes = ArrayList<Duration>()
            try {
                val events = EventBlock<Int>()
                val hostSource = host.source("slow-numbers", EventBlock<Int>())
                hostSource.then(host.chain("slow-double") { x: Int -> 2 * x })
                host.chain("slow-square") { x: Int -> x * x }.toBlock() // a chain called becomes a service
                val numbers = other.source("slow-numbers", events)
                val doubled = numbers.then(other.chain("slow-double") { x: Int -> 2 * x }).reader()
                val square = other.chain("slow-square") { x: Int -> x * x }.toBlock()
                val startHost = timed { host.start() }
                val startOther = timed { other.start() }

                // a flow: frames of many values, then single values, read by the other process
                val received = ArrayList<Int>()
                val all = CountDownLatch(1)
                val reading = Thread({ collect(doubled, VALUES, received, all) }, "slow-link-reader").apply { start() }
                val flowStarted = System.nanoTime()
                val framed = VALUES - SINGLES
                for (from in 0 until framed step FRAME) other.publishAll(numbers, (from until minOf(from + FRAME, framed)).toList())
                val framedPublished = System.nanoTime()
                (framed until VALUES).forEach(events::publish)
                val singlesPublished = System.nanoTime()
                assertTrue(all.await(PATIENCE_S, TimeUnit.SECONDS), "all values arrive; ${received.size} of $VALUES did")
                val flowTook = Duration.ofNanos(System.nanoTime() - flowStarted)
                reading.join(TimeUnit.SECONDS.toMillis(PATIENCE_S))
                assertEquals((0 until VALUES).map { 2 * it }, synchronized(received) { received.toList() }, "once each, in order")

                // calls, until both cores have run two lease times (their heartbeats renewed and looked for the dead)
                val calls = ArrayList<Duration>()
                var x = 0
                while (calls.size < MIN_CALLS || (System.nanoTime() - began < 2 * LEASE.toNanos() && calls.size < MAX_CALLS)) {
                    x++
                    val t = System.nanoTime()
                    assertEquals(x * x, square.process(x))
                    calls += Duration.ofNanos(System.nanoTime() - t)
                }
                val ran = Duration.ofNanos(System.nanoTime() - began)

                closes += timed { other.close() }
                closes += timed { host.close() }
                val sorted = calls.sorted()
                println(
                    "[slow link] reply delay ${DELAY_MS} ms: start ${startHost.toMillis()} ms (host), ${startOther.toMillis()} ms (other); " +
                        "flow of $VALUES values in ${flowTook.toMillis()} ms (${VALUES * 1000 / flowTook.toMillis().coerceAtLeast(1)} values/s; " +
                        "${framed} in frames of $FRAME published in ${(framedPublished - flowStarted) / 1_000_000} ms, " +
                        "$SINGLES single publishes in ${(singlesPublished - framedPublished) / 1_000_000} ms); " +
                        "${calls.size} calls: median ${sorted[sorted.size / 2].toMillis()} ms, max ${sorted.last().toMillis()} ms; " +
                        "ran ${ran.toMillis()} ms; close ${closes.map { it.toMillis() }} ms; " +
                        "resets ${host.redisResets()}+${other.redisResets()}",
                )
                assertTrue(sorted.last() < CALL_BOUND, "every call within $CALL_BOUND: $sorted")
                assertEquals(0L, host.redisResets() + other.redisResets(), "Redis lost nothing")
            } finally {
                if (!other.isClosed) other.close()
                if (!host.isClosed) host.close()
            }
            val ourLines = err.lines().filter { line -> (" WARN " in line || " ERROR " in line) && OURS.any { it in line } }
            assertEquals(listOf<String>(), ourLines, "no lease lapsed, nobody taken for dead, Redis never lost")
            closes.forEach { assertTrue(it < config.shutdownTimeout(), "close took $it") }
            ConformanceBase.assertNoThreadsLeft(host)
            ConformanceBase.assertNoThreadsLeft(other)
            assertEquals(0, clientsLeft(name), "connections left behind")
        } }
    }

    /**
     * A heartbeat renews the lease, then looks after host leases and dead instances, about five
     * round trips in all: over a link of 300 ms that is most of a 2 s lease. Its renewals must
     * still come a third of the lease apart (or back to back, when a beat takes longer), not a
     * third of the lease after the end of the last beat, which is 2.2 s here: no lease lapses.
     */
    @Test
    fun theHeartbeatsOwnRoundTripsDoNotStretchTheTimeBetweenRenewals() {
        val name = "slow-beat"
        val config = CoreConfig.builder().name(name).build()
        val lease = Duration.ofSeconds(2)
        val err = CapturedStderr()
        err.use { FaultProxy(TestRedis.url, Duration.ofMillis(300).toNanos()).use { proxy ->
            fun core(vararg hosts: String) = OptimusCore.builder().config(config).redis(proxy.url).leaseTime(lease).hosts(*hosts).build()
            core("slow-beat-square").use { host ->
                core().use { other ->
                    host.chain("slow-beat-square") { x: Int -> x * x }.toBlock()
                    val square = other.chain("slow-beat-square") { x: Int -> x * x }.toBlock()
                    host.start()
                    other.start()
                    val began = System.nanoTime()
                    var x = 0
                    // calls (two round trips each) while both heartbeats run three lease times
                    while (System.nanoTime() - began < 3 * lease.toNanos() && x < MAX_CALLS) {
                        x++
                        assertEquals(x * x, square.process(x))
                    }
                    assertEquals(0L, host.redisResets() + other.redisResets(), "Redis lost nothing")
                }
            }
            val ourLines = err.lines().filter { line -> (" WARN " in line || " ERROR " in line) && name in line }
            assertEquals(listOf<String>(), ourLines, "no lease lapsed, nobody taken for dead")
        } }
    }

    /** Takes [count] values from [reader] into [into] (bounded in count and time), then counts [done] down. */
    private fun collect(reader: Reader<Int>, count: Int, into: MutableList<Int>, done: CountDownLatch) {
        val deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(PATIENCE_S)
        while (synchronized(into) { into.size } < count && System.nanoTime() < deadline) {
            val value = reader.take(Duration.ofSeconds(1))
            if (value.isPresent) synchronized(into) { into += value.get() }
        }
        done.countDown()
    }

    /**
     * The connections of [topology] Redis still lists: the proxy closes each upstream connection
     * just after its client's, so this polls in bounded steps until none is left or a deadline.
     */
    private fun clientsLeft(topology: String): Int = Jedis(URI(TestRedis.url)).use { jedis ->
        val deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(5)
        val step = CountDownLatch(1)
        var left: Int
        do {
            left = jedis.clientList().lines().count { "name=prime-$topology " in it || "name=prime-$topology-" in it }
            if (left == 0) break
            step.await(20, TimeUnit.MILLISECONDS) // a bounded poll of a state only Redis shows
        } while (System.nanoTime() < deadline)
        left
    }

    private fun timed(action: () -> Unit): Duration {
        val t = System.nanoTime()
        action()
        return Duration.ofNanos(System.nanoTime() - t)
    }

    private companion object {
        val DELAY_MS: Long = System.getProperty("prime.slowLink.delayMs", "50").toLong()
        val LEASE: Duration = Duration.ofSeconds(5) // the default lease time
        const val VALUES = 300
        const val SINGLES = 60
        const val FRAME = 20
        const val MIN_CALLS = 20
        const val MAX_CALLS = 500
        const val PATIENCE_S = 60L
        val CALL_BOUND: Duration = Duration.ofSeconds(2)
        val OURS = listOf("slow-link", "slow-double", "slow-square", "slow-numbers", "lease", "Redis lost")
    }
}

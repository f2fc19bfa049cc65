package dev.prime.optimus

import dev.prime.PrimeException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.concurrent.CopyOnWriteArrayList
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * A call whose caller gave up after a service took the request ([AbandonedCalls]): an isolated
 * chain it waits for does not run it, and what that leaves in Redis.
 */
class AbandonedCallTest {

    @Test
    fun aCallThatTimesOutWaitingForAnIsolatedChainIsNotRun() {
        val entered = CountDownLatch(1)
        val release = CountDownLatch(1)
        val ran = CopyOnWriteArrayList<Int>()
        OptimusCore.builder().redis(TestRedis.url).callTimeout(Duration.ofSeconds(1)).build().use { core ->
            val isolated = core.isolate(
                core.chain("arm") { x: Int ->
                    ran += x
                    if (x == 1) {
                        entered.countDown()
                        release.await(20, TimeUnit.SECONDS)
                    }
                    x
                },
            )
            val holder = isolated.newUser().toBlock()
            val waiter = isolated.newUser().toBlock()
            core.start()
            val holding = Thread { runCatching { holder.process(1) } }.apply { isDaemon = true; start() } // it times out too
            try {
                assertTrue(entered.await(20, TimeUnit.SECONDS), "the holder's call reached the isolated chain")
                val failure = assertThrows(PrimeException::class.java) { waiter.process(2) }
                assertTrue(failure.message!!.contains("did not reply within"), failure.message)
            } finally {
                release.countDown()
                holding.join(20_000)
            }
            // the waiter's service takes its calls in order: had it run 2, it would have done so before 3
            assertEquals(3, waiter.process(3))
            // Three calls timed out after a service took them: the holder's call (its user's service
            // held the isolated chain), that service's call of the shared chain's own service (which
            // ran the block, waiting for the release) and the waiter's call.
            Jedis(URI(TestRedis.url)).use { raw ->
                val marks = TestRedis.keysOf(raw, core.name()).filter { it.endsWith(":abandoned") }
                assertEquals(3, marks.size, "each call a service took and its caller gave up is marked: $marks")
                marks.forEach {
                    val ttl = raw.pttl(it)
                    assertTrue(ttl in 1..AbandonedCalls.MARK_MILLIS, "the mark $it expires (PTTL $ttl ms)")
                }
            }
            assertEquals(listOf(1, 3), ran, "the isolated block did not run for the call that timed out")
        }
    }

    @Test
    fun aCallTakenBackFromTheQueueLeavesNoMark() {
        OptimusCore.builder().redis(TestRedis.url).hosts(emptyList()).callTimeout(Duration.ofMillis(300)).build().use { core ->
            val nobody = core.chain("unhosted") { x: Int -> x }.toBlock() // hosted by no process
            core.start()
            repeat(3) { assertThrows(PrimeException::class.java) { nobody.process(it) } }
            Jedis(URI(TestRedis.url)).use { raw ->
                assertEquals(0L, raw.llen(core.keys.serviceInput("unhosted")), "every request was taken back")
                assertEquals(
                    emptyList<String>(),
                    TestRedis.keysOf(raw, core.name()).filter { it.endsWith(":abandoned") },
                    "no request a service held: no mark",
                )
            }
        }
    }
}

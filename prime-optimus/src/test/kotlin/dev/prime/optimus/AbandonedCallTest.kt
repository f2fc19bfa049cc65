package dev.prime.optimus

import dev.prime.Block
import dev.prime.CoreConfig
import dev.prime.PrimeException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.concurrent.CompletableFuture
import java.util.concurrent.CopyOnWriteArrayList
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * A call whose caller gave up after a service took the request ([AbandonedCalls]): an isolated
 * chain it waits for does not run it, and what that leaves in Redis.
 */
class AbandonedCallTest {

    /**
     * Only the waiter's call times out: the process that hosts the services (and makes the
     * holder's call) waits far longer, so the isolated chain comes free only when the test releases
     * it, after the waiter's caller gave up. (Had the holder's own calls a timeout as short, the
     * chain could come free by their timeout a moment before the waiter's caller gives up, and the
     * waiter's service would rightly run call 2.)
     */
    @Test
    fun aCallThatTimesOutWaitingForAnIsolatedChainIsNotRun() {
        val entered = CountDownLatch(1)
        val release = CountDownLatch(1)
        val ran = CopyOnWriteArrayList<Int>()
        val config = CoreConfig.builder().name("abandoned-${System.nanoTime()}").build()
        fun OptimusCore.users(): Pair<Block<Int, Int>, Block<Int, Int>> {
            val isolated = isolate(
                chain("arm") { x: Int ->
                    ran += x
                    if (x == 1) {
                        entered.countDown()
                        release.await(20, TimeUnit.SECONDS)
                    }
                    x
                },
            )
            return isolated.newUser().toBlock() to isolated.newUser().toBlock()
        }
        OptimusCore.builder().config(config).redis(TestRedis.url).callTimeout(Duration.ofSeconds(30)).build().use { host ->
            val (holder, _) = host.users()
            host.start()
            OptimusCore.builder().config(config).redis(TestRedis.url).hosts(emptyList()).callTimeout(Duration.ofSeconds(1))
                .build().use { caller ->
                    val (_, waiter) = caller.users()
                    caller.start()
                    val held = CompletableFuture.supplyAsync { holder.process(1) }
                    try {
                        assertTrue(entered.await(20, TimeUnit.SECONDS), "the holder's call reached the isolated chain")
                        val failure = assertThrows(PrimeException::class.java) { waiter.process(2) }
                        assertTrue(failure.message!!.contains("did not reply within"), failure.message)
                    } finally {
                        release.countDown()
                    }
                    assertEquals(1, held.get(20, TimeUnit.SECONDS), "the holder's call returns once the chain is released")
                    // the waiter's service takes its calls in order: had it run 2, it would have done so before 3
                    assertEquals(3, waiter.process(3))
                    Jedis(URI(TestRedis.url)).use { raw ->
                        val marks = TestRedis.keysOf(raw, host.name()).filter { it.endsWith(":abandoned") }
                        assertEquals(1, marks.size, "the waiter's call, which its service took and its caller gave up, is marked: $marks")
                        val ttl = raw.pttl(marks.single())
                        assertTrue(ttl in 1..AbandonedCalls.MARK_MILLIS, "the mark ${marks.single()} expires (PTTL $ttl ms)")
                    }
                    assertEquals(listOf(1, 3), ran, "the isolated block did not run for the call that timed out")
                }
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

package dev.prime.optimus

import dev.prime.Block
import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import redis.clients.jedis.args.ListDirection
import java.net.URI
import java.time.Duration
import java.util.Optional
import java.util.concurrent.Executors
import java.util.concurrent.Future
import java.util.concurrent.TimeUnit

/**
 * An entry that another connection moves from a service's input into its processing list while
 * the service works (what an earlier host's blocking take does when Redis runs it after the host
 * lease changed hands: a take written behind a step that was then fenced, or one still waiting in
 * Redis for a host that was frozen or cut off) is processed like any other, in its place: the
 * service's next step sees that the list holds more than it took, stores nothing, and reads the
 * list again. Before, the step acknowledged the head of the list in place of the entry it had
 * handled, so the stray entry was dropped unprocessed and a handled one stayed behind.
 */
class StrayEntryTest {

    @Test
    fun aStrayEntryInAServicesProcessingListIsProcessedOnceAndInOrder() {
        val name = "stray-entry-flow"
        val keys = Keys(name)
        val gate = BlockGate()
        Jedis(URI(TestRedis.url)).use { jedis ->
            OptimusCore.builder().config(CoreConfig.builder().name(name).build()).redis(TestRedis.url).build().use { host ->
                val events = EventBlock<Int>()
                val output = host.source("numbers", events).then(
                    host.chain("double") { x: Int ->
                        if (x == 1) gate.hold()
                        2 * x
                    },
                ).reader()
                host.start()
                (1..5).forEach(events::publish)
                assertTrue(gate.awaitHeld(), "the service took the first value")
                awaitLength(jedis, keys.serviceInput("double"), 4)
                strayMove(jedis, keys.serviceInput("double"), keys.serviceProcessing("double"))
                gate.open()

                val received = (1..5).map { i ->
                    output.take(PATIENCE).orElseThrow { AssertionError("value $i of 5 did not arrive within $PATIENCE") }
                }
                assertEquals(listOf(2, 4, 6, 8, 10), received, "every value once, in order")
                assertEquals(Optional.empty<Int>(), output.take(Duration.ofSeconds(1)), "no duplicates")
                assertEquals(0L, jedis.llen(keys.serviceProcessing("double")), "everything acknowledged, nothing left behind")
            }
        }
    }

    @Test
    fun aStrayRequestInACalledServicesProcessingListIsAnswered() {
        val name = "stray-entry-call"
        val keys = Keys(name)
        val first = BlockGate()
        val second = BlockGate()
        val callers = Executors.newFixedThreadPool(4)
        try {
            Jedis(URI(TestRedis.url)).use { jedis ->
                OptimusCore.builder().config(CoreConfig.builder().name(name).build()).redis(TestRedis.url)
                    .callTimeout(CALL_TIMEOUT).build().use { host ->
                        val echo = echo(host, mapOf(0 to first, 1 to second))
                        host.start()
                        assertEquals(200, echo.process(100), "warm: the service is idle in its watched take")
                        val calls = ArrayList<Future<Int>>()
                        calls += callers.submit<Int> { echo.process(0) }
                        assertTrue(first.awaitHeld(), "the service took request 0")
                        for (x in 1..3) {
                            calls += callers.submit<Int> { echo.process(x) }
                            awaitLength(jedis, keys.serviceInput("echo"), x.toLong())
                        }
                        // the step of request 0 takes request 1 behind it; 2 and 3 wait in the input
                        first.open()
                        assertTrue(second.awaitHeld(), "the service took request 1")
                        awaitLength(jedis, keys.serviceInput("echo"), 2)
                        strayMove(jedis, keys.serviceInput("echo"), keys.serviceProcessing("echo"))
                        second.open()

                        val answers = answersOf(calls)
                        assertEquals(listOf(100, 101, 102, 103), answers, "every request answered")
                        assertEquals(0L, jedis.llen(keys.serviceProcessing("echo")), "everything acknowledged, nothing left behind")
                        assertEquals(0L, jedis.llen(keys.deadLetters("echo")), "no dead letter")
                    }
            }
        } finally {
            callers.shutdownNow()
        }
    }

    /**
     * Two faults at once: an earlier host's blocking take, still waiting in Redis, is served
     * before this host's take (so the stray request is at the head of the processing list), and
     * the host lease lapses while the service handles the request behind it. The step finds the
     * lease held by nobody, stores nothing and reads the list again once it re-claimed the lease,
     * stray request first: every request is answered (once, that step acknowledged the stray
     * request unread in place of the handled one).
     */
    @Test
    fun aStrayRequestAtTheHeadOfTheListIsAnsweredWhenTheLeaseLapsedMeanwhile() {
        val name = "stray-entry-lapse"
        val keys = Keys(name)
        val first = BlockGate()
        val third = BlockGate()
        val callers = Executors.newFixedThreadPool(4)
        try {
            // a Redis of its own: the test counts the clients blocked in it
            EmbeddedRedis.start().use { redis ->
                Jedis(URI(redis.uri)).use { jedis ->
                    OptimusCore.builder().config(CoreConfig.builder().name(name).build()).redis(redis.uri)
                        .leaseTime(LAPSE_LEASE).callTimeout(CALL_TIMEOUT).build().use { host ->
                            val echo = echo(host, mapOf(0 to first, 2 to third))
                            host.start()
                            assertEquals(200, echo.process(100), "warm")
                            val calls = ArrayList<Future<Int>>()
                            calls += callers.submit<Int> { echo.process(0) }
                            assertTrue(first.awaitHeld(), "the service took request 0")
                            // the earlier host's take, waiting in Redis ahead of the service's next one
                            val input = keys.serviceInput("echo")
                            val processing = keys.serviceProcessing("echo")
                            val earlierTake = callers.submit<ByteArray?> {
                                Jedis(URI(redis.uri)).use { it.blmove(input, processing, ListDirection.LEFT, ListDirection.RIGHT, 10.0) }
                            }
                            awaitBlocked(jedis, 2) // request 0's caller and the earlier take (the service is in its block)
                            first.open()
                            assertEquals(100, calls[0].get(PATIENCE.seconds, TimeUnit.SECONDS))
                            awaitBlocked(jedis, 2) // the earlier take and the service's take behind it
                            calls += callers.submit<Int> { echo.process(1) }
                            assertTrue(earlierTake.get(PATIENCE.seconds, TimeUnit.SECONDS) != null, "the earlier take moved request 1")
                            calls += callers.submit<Int> { echo.process(2) }
                            assertTrue(third.awaitHeld(), "the service took request 2")
                            assertEquals(2L, jedis.llen(processing), "request 1 (stray, at the head) and request 2")
                            assertEquals(1L, jedis.del(keys.hostLease("echo")), "the lease lapses")
                            third.open()

                            val answers = answersOf(calls)
                            assertEquals(listOf(100, 101, 102), answers, "every request answered")
                            assertEquals(0L, jedis.llen(processing), "everything acknowledged, nothing left behind")
                        }
                }
            }
        } finally {
            callers.shutdownNow()
        }
    }

    /** Service `echo` (x + 100), whose block holds at each gate's input. */
    private fun echo(host: OptimusCore, gates: Map<Int, BlockGate>): Block<Int, Int> =
        host.chain("echo") { x: Int ->
            gates[x]?.hold()
            x + 100
        }.toBlock()

    /** The calls' answers, in order; fails naming the first request not answered. */
    private fun answersOf(calls: List<Future<Int>>): List<Int> = calls.mapIndexed { x, call ->
        try {
            call.get(PATIENCE.seconds, TimeUnit.SECONDS)
        } catch (e: java.util.concurrent.ExecutionException) {
            throw AssertionError("request $x was not answered: ${e.cause}", e.cause)
        }
    }

    /** The number of clients blocked in Redis (a caller waiting for its reply, a service in its take). */
    private fun blockedClients(jedis: Jedis): Int =
        jedis.info("clients").lines().first { it.startsWith("blocked_clients:") }.substringAfter(':').trim().toInt()

    /** Waits (bounded) until [count] clients are blocked in Redis. */
    private fun awaitBlocked(jedis: Jedis, count: Int) {
        val deadline = System.nanoTime() + PATIENCE.toNanos()
        while (blockedClients(jedis) != count) {
            check(System.nanoTime() < deadline) { "${blockedClients(jedis)} clients blocked, not $count, after $PATIENCE" }
            Thread.onSpinWait()
        }
    }

    /** Moves the input's head to the processing list's tail, as an earlier host's blocking take does. */
    private fun strayMove(jedis: Jedis, input: ByteArray, processing: ByteArray) {
        val moved = jedis.lmove(input, processing, ListDirection.LEFT, ListDirection.RIGHT)
        assertTrue(moved != null, "an entry was there to move")
        assertEquals(2L, jedis.llen(processing), "the entry the service holds and the stray one")
    }

    /** Waits (bounded) until [list] holds [length] entries. */
    private fun awaitLength(jedis: Jedis, list: ByteArray, length: Long) {
        val deadline = System.nanoTime() + PATIENCE.toNanos()
        while (jedis.llen(list) != length) {
            check(System.nanoTime() < deadline) { "the list held ${jedis.llen(list)} entries, not $length, after $PATIENCE" }
            Thread.onSpinWait()
        }
    }

    private companion object {
        val CALL_TIMEOUT: Duration = Duration.ofSeconds(5)
        val LAPSE_LEASE: Duration = Duration.ofSeconds(3)
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

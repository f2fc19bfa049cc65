package dev.prime.optimus

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
import java.util.concurrent.CompletableFuture
import java.util.concurrent.TimeUnit
import java.util.concurrent.locks.LockSupport

/**
 * A timed take whose blocking wait Redis answers later than the deadline plus
 * [RedisConnections.BLOCKING_DEADLINE_GRACE_MS] (a loaded machine, here a proxy that holds replies back)
 * returns empty, as the Reader contract says for "nothing came in time", within the timeout plus
 * about a second, instead of reporting Redis unreachable; a value that late wait moved into the
 * reader's processing list is delivered by the next take, exactly once.
 */
class LateBlockingReplyTest {

    @Test
    fun aTimedTakeAnsweredAfterItsDeadlineAndGraceReturnsEmptyInTime() {
        Fixture().use { f ->
            // every reply comes this late: the take's step in time, its blocking wait's nil after deadline + grace
            f.proxy.replyDelayNanos = Duration.ofMillis(RedisConnections.BLOCKING_DEADLINE_GRACE_MS + DELAY_PAST_GRACE_MS).toNanos()
            val started = System.nanoTime()
            val got = f.reader.take(TIMEOUT)
            val took = Duration.ofNanos(System.nanoTime() - started)
            f.proxy.replyDelayNanos = 0
            println("a take(${TIMEOUT.toMillis()} ms) answered late returned $got after ${took.toMillis()} ms")
            assertEquals(Optional.empty<Int>(), got, "nothing came in time")
            assertTrue(took >= TIMEOUT, "returned before its timeout: $took")
            assertTrue(took <= TIMEOUT.plus(BOUND), "held $took, more than the timeout plus $BOUND")

            f.events.publish(2)
            assertEquals(2, f.reader.take(PATIENCE).orElseThrow(), "the reader works on after the late reply")
            assertEquals(Optional.empty<Int>(), f.reader.poll())
        }
    }

    @Test
    fun aValueMovedByAWaitAnsweredTooLateIsDeliveredByTheNextTakeOnce() {
        Fixture().use { f ->
            // a genuine entry of the reader, parked aside so that it can arrive while the take waits
            f.events.publish(42)
            assertEquals(1L, f.redis.llen(f.list), "the published value is in the reader's list")
            f.redis.lmove(f.list, f.stash, ListDirection.LEFT, ListDirection.RIGHT)

            val take = CompletableFuture.supplyAsync { f.reader.take(TIMEOUT) }
            f.awaitBlockedWait()
            // from now on Redis's replies are held back well past the take's deadline plus grace
            f.proxy.replyDelayNanos = TIMEOUT.plusMillis(RedisConnections.BLOCKING_DEADLINE_GRACE_MS).plus(BOUND).toNanos()
            f.redis.lmove(f.stash, f.list, ListDirection.LEFT, ListDirection.RIGHT) // Redis serves the waiting BLMOVE at once
            val got = take.get(PATIENCE.toMillis(), TimeUnit.MILLISECONDS)
            f.proxy.replyDelayNanos = 0
            assertEquals(Optional.empty<Int>(), got, "the wait's reply came too late: nothing in time")
            assertEquals(0L, f.redis.llen(f.list), "the late wait took the value from the reader's list")
            assertEquals(1L, f.redis.llen(f.processing), "the late wait moved the value into the processing list")

            assertEquals(42, f.reader.take(PATIENCE).orElseThrow(), "the next take delivers the moved value")
            f.events.publish(43)
            assertEquals(43, f.reader.take(PATIENCE).orElseThrow(), "the moved value is not delivered twice")
            assertEquals(Optional.empty<Int>(), f.reader.poll(), "nothing else")
        }
    }

    /** A core behind a reply-delaying proxy with a reader whose connection is open, and a direct connection to Redis. */
    private class Fixture : AutoCloseable {
        val proxy = FaultProxy(TestRedis.url)
        private val name = "late-reply-${System.nanoTime()}"
        val core: OptimusCore = OptimusCore.builder().config(CoreConfig.builder().name(name).build()).redis(proxy.url).build()
        val events = EventBlock<Int>()
        val reader = core.source(events).reader()
        val list = (reader as OptimusReader<*>).list
        val processing = core.keys.processingOf(list)
        val stash = "$name:stash".toByteArray()
        val redis = Jedis(URI(TestRedis.url))

        init {
            core.start()
            events.publish(1)
            assertEquals(1, reader.take(PATIENCE).orElseThrow(), "works before the replies slow down")
        }

        /** Until Redis holds the reader's `BLMOVE` waiting (bounded by [PATIENCE]). */
        fun awaitBlockedWait() {
            val until = System.nanoTime() + PATIENCE.toNanos()
            while (System.nanoTime() - until < 0) {
                val waiting = redis.clientList().lines().any { "name=prime-$name " in it && "cmd=blmove" in it && Regex("flags=\\S*b").containsMatchIn(it) }
                if (waiting) return
                LockSupport.parkNanos(POLL_NANOS)
            }
            throw AssertionError("the reader's BLMOVE did not wait in Redis within $PATIENCE")
        }

        override fun close() {
            proxy.replyDelayNanos = 0
            try {
                redis.del(stash)
                redis.close()
                core.close()
            } finally {
                proxy.close()
            }
        }
    }

    private companion object {
        /** One server wait of the reader (at most [RedisConnections.POLL_SECONDS]): the whole timeout. */
        val TIMEOUT: Duration = Duration.ofMillis(1000)

        /** The Reader contract's bound past a timeout ("plus about a second"). */
        val BOUND: Duration = Duration.ofSeconds(1)
        val PATIENCE: Duration = Duration.ofSeconds(20)
        const val DELAY_PAST_GRACE_MS = 300L
        const val POLL_NANOS = 1_000_000L
    }
}

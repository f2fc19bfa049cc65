package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.concurrent.CompletableFuture
import java.util.concurrent.ExecutionException
import java.util.concurrent.TimeUnit

/** A closed Optimus reader leaves the source's reader set and deletes its lists; nothing keeps writing to it. */
class ReaderCloseTest {

    @Test
    fun aClosedReaderLeavesNothingInRedis() {
        TestRedis.core().use { core ->
            val events = EventBlock<Int>()
            val source = core.source("closing", events)
            val reader = source.reader() as OptimusReader<Int>
            val other = source.reader()
            core.start()
            events.publish(1)
            events.publish(2)
            assertEquals(1, reader.take(PATIENCE).orElseThrow()) // one taken, one waiting in its list
            val readers = core.keys.sourceReaders("closing")
            Jedis(URI(TestRedis.url)).use { redis ->
                assertEquals(2L, redis.scard(readers))
                reader.close()
                assertFalse(redis.sismember(readers, reader.list), "the reader left the source's reader set")
                assertEquals(1L, redis.scard(readers))
                events.publish(3)
                assertEquals(listOf(1, 2, 3), (1..3).map { other.take(PATIENCE).orElseThrow() })
                val left = listOf(reader.list, core.keys.processingOf(reader.list), core.keys.missedOf(reader.list))
                    .count { redis.exists(it) }
                assertEquals(0, left, "lists of the closed reader left in Redis")
            }
        }
    }

    @Test
    fun aClosedCoreLeavesNoReplyListBehind() {
        val core = TestRedis.core()
        val name = core.name()
        core.use {
            val call = it.chain("echo") { x: Int -> x }.toBlock()
            it.start()
            assertEquals(5, call.process(5))
        }
        Jedis(URI(TestRedis.url)).use { redis ->
            assertEquals(emptySet<String>(), redis.keys("prime:{$name}:reply:*"), "reply lists left behind")
        }
    }

    /**
     * Reader: "a call blocked in take() ends with IllegalStateException" at close(). While Redis is
     * down a take waits between attempts to reconnect (up to a second each); close() ends that wait too.
     */
    @Test
    fun closeEndsATakeWaitingOutAnOutageAtOnce() {
        EmbeddedRedis.start().use { redis ->
            OptimusCore.builder().config(CoreConfig.builder().name("close-in-outage-${System.nanoTime()}").build()).redis(redis.uri).build().use { core ->
                val events = EventBlock<Int>()
                val source = core.source("outage", events)
                val readers = (1..READERS).map { source.reader() }
                core.start()
                redis.kill()
                val takes = readers.map { reader -> CompletableFuture.supplyAsync { reader.take() } }
                // long enough for the waits between attempts to reach their longest, a second
                assertThrows<java.util.concurrent.TimeoutException> { takes[0].get(OUTAGE_MS, TimeUnit.MILLISECONDS) }
                val ended = readers.zip(takes).map { (reader, take) ->
                    val closing = System.nanoTime()
                    CompletableFuture.runAsync(reader::close) // close() itself may wait for Redis (at most 2 s)
                    val e = assertThrows<ExecutionException> { take.get(PATIENCE.toMillis(), TimeUnit.MILLISECONDS) }
                    assertTrue(e.cause is IllegalStateException && e.cause!!.message!!.startsWith("reader closed"), "the take ends with 'reader closed', not ${e.cause}")
                    (System.nanoTime() - closing) / 1_000_000
                }
                println("takes ended ${ended.joinToString()} ms after their readers' close()")
                assertTrue(ended.all { it < CLOSE_WAKES_MS }, "every take ends within $CLOSE_WAKES_MS ms of close(): $ended ms")
            }
        }
    }

    private inline fun <reified E : Throwable> assertThrows(noinline action: () -> Unit): E =
        org.junit.jupiter.api.Assertions.assertThrows(E::class.java, action)

    private companion object {
        val PATIENCE: Duration = Duration.ofSeconds(20)
        const val READERS = 5
        const val OUTAGE_MS = 2500L
        const val CLOSE_WAKES_MS = 250L
    }
}

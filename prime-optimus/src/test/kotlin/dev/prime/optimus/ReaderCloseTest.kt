package dev.prime.optimus

import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration

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

    private companion object {
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

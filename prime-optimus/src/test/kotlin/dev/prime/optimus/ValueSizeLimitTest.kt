package dev.prime.optimus

import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.Optional

/** Values above `maxValueBytes` are refused where they are given; entries above it found in Redis are dead-lettered with a prefix. */
class ValueSizeLimitTest {

    @Test
    fun anOversizeValueIsRefusedAtPublishAndAtCall() {
        OptimusCore.builder().redis(TestRedis.url).maxValueBytes(LIMIT).build().use { core ->
            val events = EventBlock<ByteArray>()
            val blobs = core.source("blobs", events)
            val reader = blobs.reader()
            val size = core.chain("size") { b: ByteArray -> b.size }.toBlock()
            core.start()

            val atPublish = assertThrows(ValueTooLargeException::class.java) { events.publish(ByteArray(2 * LIMIT)) }
            assertTrue("$LIMIT" in atPublish.message!!, atPublish.message)
            assertTrue("maxValueBytes" in atPublish.message!!, atPublish.message)
            assertThrows(ValueTooLargeException::class.java) { core.publishAll(blobs, listOf(ByteArray(1), ByteArray(2 * LIMIT))) }
            assertEquals(Optional.empty<ByteArray>(), reader.poll(), "nothing of a refused publish was published")

            assertThrows(ValueTooLargeException::class.java) { size.process(ByteArray(2 * LIMIT)) }
            assertEquals(10, size.process(ByteArray(10)), "the chain still answers")
        }
    }

    @Test
    fun theRefusalNamesTheTypeItsSizeAndTheLimit() {
        OptimusCore.builder().redis(TestRedis.url).maxValueBytes(LIMIT).build().use { core ->
            val events = EventBlock<String>()
            core.source("texts", events)
            core.start()
            val text = "x".repeat(2 * LIMIT)
            val size = core.codec.encode(text).size
            val refused = assertThrows(ValueTooLargeException::class.java) { events.publish(text) }
            val message = refused.message!!
            assertTrue("java.lang.String" in message && "$size bytes" in message && "limit of $LIMIT bytes" in message, message)
        }
    }

    @Test
    fun oversizeEntriesFoundInRedisAreDeadLetteredWithOnlyAPrefixKept() {
        OptimusCore.builder().redis(TestRedis.url).maxValueBytes(LIMIT).build().use { core ->
            val events = EventBlock<Int>()
            val out = core.source("numbers", events).then(core.chain("inc") { x: Int -> x + 1 }).reader()
            core.start()
            Jedis(URI(TestRedis.url)).use { raw ->
                repeat(3) { i -> raw.rpush(core.keys.serviceInput("inc"), Envelope.value(1000L + i, ByteArray(HUGE) { 7 })) }
            }
            events.publish(1)
            assertEquals(2, out.take(PATIENCE).orElseThrow())
            val letters = core.deadLetters("inc")
            assertEquals(3, letters.size, letters.toString())
            for (letter in letters) {
                assertTrue(letter.bytes().size <= DeadLetter.PREFIX_KEPT, "a dead letter kept ${letter.bytes().size} bytes")
                assertTrue("over the limit" in letter.reason && "${HUGE + 11}" in letter.reason, letter.reason)
            }
        }
    }

    @Test
    fun aValueOfExactlyTheLimitIsPublishedAndOneByteMoreIsRefused() {
        OptimusCore.builder().redis(TestRedis.url).maxValueBytes(LIMIT).build().use { core ->
            val events = EventBlock<ByteArray>()
            val reader = core.source("edge", events).reader()
            core.start()
            val overhead = core.codec.encode(ByteArray(LIMIT)).size - LIMIT
            val atLimit = ByteArray(LIMIT - overhead) { 3 }
            assertEquals(LIMIT, core.codec.encode(atLimit).size, "the value encodes to exactly the limit")
            events.publish(atLimit)
            assertEquals(atLimit.size, reader.take(PATIENCE).orElseThrow().size)
            val over = assertThrows(ValueTooLargeException::class.java) { events.publish(ByteArray(atLimit.size + 1)) }
            assertTrue("${LIMIT + 1} bytes" in over.message!!, over.message)
        }
    }

    private companion object {
        const val LIMIT = 64 * 1024
        const val HUGE = 3 * 1024 * 1024
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

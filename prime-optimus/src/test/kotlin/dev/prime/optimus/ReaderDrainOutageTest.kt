package dev.prime.optimus

import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration

/**
 * A reader's `drain()` that meets an unreachable Redis after it handed out values of a frame it
 * had read: it returns them (they count as delivered), and the reader goes on once Redis is back;
 * a `poll()` hands those values out one by one, then throws at once.
 */
class ReaderDrainOutageTest {

    @Test
    fun aDrainThatMeetsAnUnreachableRedisReturnsTheValuesItHadCollected() {
        withProxiedReaderCore("drain-outage") { publisher, numbers, proxy, readerCore ->
            val reader = readerCore.source("numbers", EventBlock<Int>()).reader()
            readerCore.start()
            publisher.publishAll(numbers, (1..100).toList()) // one frame
            val received = ArrayList<Int>()
            received += reader.take(Duration.ofSeconds(10)).orElseThrow() // the rest of the frame waits in the reader
            proxy.refuse() // Redis is unreachable for the reader
            received += reader.drain()
            assertEquals((1..100).toList(), received, "the drain returned the frame's values it handed out")
            proxy.restore()
            publisher.publishAll(numbers, (101..110).toList())
            repeat(10) { received += reader.take(Duration.ofSeconds(10)).orElseThrow() }
            assertEquals((1..110).toList(), received, "every value once, in order, after Redis came back")
            assertEquals(emptyList<Int>(), reader.drain(), "nothing more")
        }
    }

    /**
     * A `poll()` while Redis is unreachable hands out the values the reader had already read (the
     * rest of a frame) without going to Redis; once they are out, it throws
     * `RedisUnavailableException` within a second, and nothing is lost once Redis is back.
     */
    @Test
    fun aPollThatMeetsAnUnreachableRedisHandsOutTheValuesItHadReadThenThrowsAtOnce() {
        withProxiedReaderCore("poll-outage") { publisher, numbers, proxy, readerCore ->
            val reader = readerCore.source("numbers", EventBlock<Int>()).reader()
            readerCore.start()
            publisher.publishAll(numbers, (1..100).toList()) // one frame
            val received = ArrayList<Int>()
            received += reader.take(Duration.ofSeconds(10)).orElseThrow() // the rest of the frame waits in the reader
            proxy.refuse() // Redis is unreachable for the reader
            repeat(99) { received += reader.poll().orElseThrow() }
            assertEquals((1..100).toList(), received, "the polls handed out the frame's values")
            val began = System.nanoTime()
            assertThrows(RedisUnavailableException::class.java) { reader.poll() }
            val millis = (System.nanoTime() - began) / 1_000_000
            assertTrue(millis < 2_000, "the poll with nothing in hand threw after $millis ms, not about a second")
            proxy.restore()
            publisher.publishAll(numbers, (101..110).toList())
            repeat(10) { received += reader.take(Duration.ofSeconds(10)).orElseThrow() }
            assertEquals((1..110).toList(), received, "every value once, in order, after Redis came back")
        }
    }
}

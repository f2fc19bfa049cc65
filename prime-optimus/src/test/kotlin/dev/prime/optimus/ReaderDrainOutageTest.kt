package dev.prime.optimus

import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import java.time.Duration

/**
 * A reader's `drain()` that meets an unreachable Redis after it handed out values of a frame it
 * had read: it returns them (they count as delivered), and the reader goes on once Redis is back.
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
}

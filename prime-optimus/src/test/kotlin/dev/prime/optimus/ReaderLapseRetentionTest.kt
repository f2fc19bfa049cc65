package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * A reader whose process was cut off longer than its lease is reclaimed by another process, and
 * registered again when its process comes back: the registration copies the whole retained log
 * into its list. With a retention larger than the default number of ids a reader remembers
 * (4096), the values it had handed out must still not come out again.
 */
class ReaderLapseRetentionTest {

    @Test
    fun aReaderRegisteredAgainAfterItsLeaseLapsedDeliversNothingTwiceWithALargeRetention() {
        val retention = 6000
        val config = CoreConfig.builder().name("lapse-${System.nanoTime()}").sourceRetention(retention).build()
        val keys = Keys(config.name())
        val lease = Duration.ofSeconds(1)
        val pace = CountDownLatch(1) // never counted down: a bounded pause between looks
        EmbeddedRedis.start().use { redis ->
            FaultProxy(redis.uri).use { proxy ->
                Jedis(URI(redis.uri)).use { raw ->
                    OptimusCore.builder().config(config).redis(redis.uri).leaseTime(lease).hosts(emptyList()).build().use { publisher ->
                        val numbers = publisher.source("numbers", EventBlock<Int>())
                        publisher.start()
                        OptimusCore.builder().config(config).redis(proxy.url).leaseTime(lease).hosts(emptyList()).build().use { readerCore ->
                            val reader = readerCore.source("numbers", EventBlock<Int>()).reader()
                            readerCore.start()
                            (1..retention).chunked(200).forEach { publisher.publishAll(numbers, it) }
                            val received = ArrayList<Int>()
                            repeat(retention) { received += reader.take(Duration.ofSeconds(10)).orElseThrow() }
                            assertEquals((1..retention).toList(), received)
                            val readers = keys.sourceReaders("numbers")

                            proxy.refuse() // the reader's process is cut off: its lease lapses, the publisher reclaims its reader
                            var looks = 0
                            while (raw.scard(readers) != 0L && looks++ < 1000) pace.await(10, TimeUnit.MILLISECONDS)
                            assertEquals(0L, raw.scard(readers), "the publisher reclaimed the cut-off reader")
                            proxy.restore()
                            looks = 0
                            while (raw.scard(readers) != 1L && looks++ < 1000) pace.await(10, TimeUnit.MILLISECONDS)
                            assertEquals(1L, raw.scard(readers), "the reader's process registered it again")

                            publisher.publishAll(numbers, listOf(retention + 1))
                            assertEquals(
                                retention + 1,
                                reader.take(Duration.ofSeconds(10)).orElse(null),
                                "the next value comes first: none of the values handed out before the lapse came out again",
                            )
                            assertEquals(emptyList<Int>(), reader.drain(), "nothing more")
                        }
                    }
                }
            }
        }
    }
}

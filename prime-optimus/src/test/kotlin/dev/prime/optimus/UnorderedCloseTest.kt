package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.Source
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.Optional
import java.util.concurrent.CompletableFuture
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicInteger

/**
 * [Hosting.UNORDERED]: "a host that closes does so at once" — it gives back what it had taken and
 * not stored before its block returns, so a surviving host processes it without waiting for the
 * closed host's lease (30 s here), and the value's result is stored once.
 */
class UnorderedCloseTest {

    @Test
    fun aClosingHostGivesBackWhatItHoldsAtOnceAndItsResultIsStoredOnce() {
        val name = "unordered-close-${System.nanoTime()}"
        val inBlock = CountDownLatch(1)
        val release = CountDownLatch(1)
        val survivorRuns = AtomicInteger()
        val closing = core(name, Hosting.UNORDERED)
        declare(closing) { x ->
            inBlock.countDown()
            release.await(PATIENCE.toSeconds(), TimeUnit.SECONDS)
            x
        }
        try {
            core(name, null).use { publisher ->
                val (numbers, output) = declare(publisher) { it }
                val reader = output.reader()
                publisher.start()
                closing.start()
                numbers.publish(7)
                assertTrue(inBlock.await(PATIENCE.toSeconds(), TimeUnit.SECONDS), "the first host took the value")
                core(name, Hosting.UNORDERED).use { survivor ->
                    declare(survivor) { x -> survivorRuns.incrementAndGet(); x }
                    survivor.start()
                    val closed = CompletableFuture.runAsync { closing.close() }
                    assertEquals(Optional.of(7), reader.take(PATIENCE), "the survivor got the value back well before the 30 s lease")
                    assertEquals(1, survivorRuns.get())
                    release.countDown()
                    closed.get(PATIENCE.toSeconds(), TimeUnit.SECONDS)
                    assertEquals(Optional.empty<Int>(), reader.poll(), "the closed host stored nothing of what it gave back")
                    Jedis(URI(TestRedis.url)).use { jedis ->
                        assertEquals(1L, TestRedis.values(jedis, publisher.keys.sourceLog(output.name())), "the result is stored once")
                    }
                }
            }
        } finally {
            release.countDown()
            closing.close()
        }
    }

    private fun core(name: String, mode: Hosting?): OptimusCore {
        val builder = OptimusCore.builder()
            .config(CoreConfig.builder().name(name).build())
            .redis(TestRedis.url)
            .leaseTime(LEASE)
        return if (mode == null) builder.hosts(emptyList()).build() else builder.hosts(SERVICE).hosting(SERVICE, mode).build()
    }

    private fun declare(core: OptimusCore, block: (Int) -> Int): Pair<EventBlock<Int>, Source<Int>> {
        val numbers = EventBlock<Int>()
        return numbers to core.source("numbers", numbers).then(core.chain(SERVICE) { x: Int -> block(x) })
    }

    private companion object {
        const val SERVICE = "held"
        val LEASE: Duration = Duration.ofSeconds(30)
        val PATIENCE: Duration = Duration.ofSeconds(10)
    }
}

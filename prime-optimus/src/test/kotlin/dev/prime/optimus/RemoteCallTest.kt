package dev.prime.optimus

import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.Optional
import java.util.concurrent.Callable
import java.util.concurrent.Executors
import java.util.concurrent.TimeUnit

/** Remote calls under concurrency, and values delivered twice. */
class RemoteCallTest {

    @Test
    fun manyConcurrentCallersEachGetTheirOwnResults() {
        val threads = 8
        val calls = 200
        val pool = Executors.newFixedThreadPool(threads)
        try {
            TestRedis.core().use { core ->
                val chain = core.link(core.chain("tag") { x: Int -> "v$x" }, core.chain("wrap") { s: String -> "[$s]" })
                core.start()
                val block = chain.toBlock()
                val futures = (0 until threads).map { t ->
                    pool.submit(Callable { (0 until calls).map { i -> block.process(t * 1000 + i) } })
                }
                futures.forEachIndexed { t, future ->
                    assertEquals((0 until calls).map { "[v${t * 1000 + it}]" }, future.get(60, TimeUnit.SECONDS))
                }
            }
        } finally {
            pool.shutdownNow()
        }
    }

    @Test
    fun aCallThatTimedOutLeavesNoRequestBehind() {
        OptimusCore.builder().redis(TestRedis.url).hosts(emptyList()).callTimeout(Duration.ofMillis(500)).build().use { core ->
            val nobody = core.chain("unhosted") { x: Int -> x }.toBlock() // hosted by no process
            core.start()
            val started = System.nanoTime()
            val e = org.junit.jupiter.api.Assertions.assertThrows(dev.prime.PrimeException::class.java) { nobody.process(1) }
            val took = Duration.ofNanos(System.nanoTime() - started)
            org.junit.jupiter.api.Assertions.assertTrue(took < Duration.ofMillis(1500), "gave up after $took: ${e.message}")
            Jedis(URI(TestRedis.url)).use { raw ->
                assertEquals(0L, raw.llen(core.keys.serviceInput("unhosted")), "the abandoned request is still queued")
            }
        }
    }

    @Test
    fun aValuePushedTwiceIsProcessedOnce() {
        TestRedis.core().use { core ->
            val events = EventBlock<Int>()
            val seen = java.util.concurrent.CopyOnWriteArrayList<Int>()
            val out = core.source(events).then(core.chain("count") { x: Int -> seen += x; x }).reader()
            core.start()
            // what a producer's retry after a lost reply leaves in the list: the same envelope twice
            val envelope = Envelope.value(77L, core.codec.encode(5))
            Jedis(URI(TestRedis.url)).use { raw ->
                raw.rpush(core.keys.serviceInput("count"), envelope, envelope)
            }
            events.publish(6)
            assertEquals(5, out.take(Duration.ofSeconds(20)).orElseThrow())
            assertEquals(6, out.take(Duration.ofSeconds(20)).orElseThrow())
            assertEquals(Optional.empty<Int>(), out.poll())
            assertEquals(listOf(5, 6), seen)
        }
    }
}

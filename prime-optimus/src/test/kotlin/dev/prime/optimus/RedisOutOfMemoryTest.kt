package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.PrimeException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.util.concurrent.CopyOnWriteArrayList
import java.util.concurrent.CountDownLatch
import java.util.concurrent.Semaphore
import java.util.concurrent.TimeUnit

/**
 * A Redis out of memory (`maxmemory` reached) stores nothing, not even a dead letter: a publish
 * is refused with a clear message, and a service waits with what it holds instead of dropping it;
 * once memory is back, every value is processed.
 */
class RedisOutOfMemoryTest {

    @Test
    fun aServiceWaitsOutARedisOutOfMemoryAndDropsNothing() {
        EmbeddedRedis.start().use { redis ->
            val config = CoreConfig.builder().name("oom").build()
            Jedis(URI(redis.uri)).use { admin ->
                val gate = CountDownLatch(1)
                val inside = CountDownLatch(1)
                val attempts = Semaphore(0)
                val seen = CopyOnWriteArrayList<Int>()
                val all = CountDownLatch(5)
                OptimusCore.builder().config(config).redis(redis.uri).hosts(emptyList()).build().use { publisher ->
                    val numbers = declare(publisher) { }.first
                    publisher.start()
                    OptimusCore.builder().config(config).redis(redis.uri).hosts("keep", "listen(numbers>keep)").build().use { worker ->
                        declare(worker) { x ->
                            inside.countDown()
                            gate.await(20, TimeUnit.SECONDS)
                            attempts.release()
                            seen += x
                        }.second.listen { all.countDown() }
                        worker.start()
                        publisher.publishAll(numbers, (1..5).toList())
                        assertTrue(inside.await(20, TimeUnit.SECONDS), "the service did not take a value")
                        admin.configSet("maxmemory", "1")
                        val refused = assertThrows(PrimeException::class.java) { publisher.publishAll(numbers, listOf(6)) }
                        assertTrue("out of memory" in refused.message!!, refused.message)
                        gate.countDown() // the service's first step now meets the full Redis

                        assertTrue(attempts.tryAcquire(1, 20, TimeUnit.SECONDS), "the service did not process")
                        // Redis counts the OOM errors it answered: the publish above, then the service's step and its retries
                        val deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(20)
                        while (oomErrors(admin) < 3 && System.nanoTime() < deadline) Thread.sleep(10)
                        assertTrue(oomErrors(admin) >= 3, "the service did not meet the full Redis twice")
                        // in values: the five travel in one frame
                        val held = TestRedis.values(admin, worker.keys.serviceInput("keep")) +
                            TestRedis.values(admin, worker.keys.serviceProcessing("keep"))
                        assertEquals(5L, held, "every value is still in the service's queue")
                        assertEquals(0L, admin.llen(worker.keys.deadLetters("keep")))
                        admin.configSet("maxmemory", "0")
                        assertTrue(all.await(20, TimeUnit.SECONDS), "${all.count} values did not come through")
                    }
                }
                assertEquals((1..5).toList(), seen.distinct())
            }
        }
    }

    /**
     * A read and a call that meet a Redis out of memory fail at once with a [PrimeException] that
     * says so, never Redis's own exception; what they met changed nothing: the value stays for the
     * next read, and calls work again once memory is back.
     */
    @Test
    fun aReadAndACallOnARedisOutOfMemoryFailWithAClearExceptionAndLoseNothing() {
        EmbeddedRedis.start().use { redis ->
            val config = CoreConfig.builder().name("oom-read-call").build()
            Jedis(URI(redis.uri)).use { admin ->
                OptimusCore.builder().config(config).redis(redis.uri).callTimeout(java.time.Duration.ofSeconds(5)).build().use { core ->
                    val numbers = core.source("numbers", EventBlock<Int>())
                    val reader = numbers.reader()
                    val double = core.chain("double") { x: Int -> 2 * x }.toBlock()
                    core.start()
                    assertEquals(2, double.process(1), "a first call (its reply list is recorded now)")
                    core.publishAll(numbers, listOf(0, 1))
                    assertEquals(0, reader.take(java.time.Duration.ofSeconds(10)).orElseThrow())
                    assertEquals(listOf(1), reader.drain(), "the rest of the frame; the next read goes to Redis with a step")
                    core.publishAll(numbers, listOf(2))
                    admin.configSet("maxmemory", "1")
                    try {
                        val read = assertThrows(PrimeException::class.java) { reader.take(java.time.Duration.ofSeconds(2)) }
                        assertTrue("reading a source refused" in read.message!! && "out of memory" in read.message!!, read.message)
                        val call = assertThrows(PrimeException::class.java) { double.process(2) }
                        assertTrue("calling chain 'double' refused" in call.message!! && "out of memory" in call.message!!, call.message)
                    } finally {
                        admin.configSet("maxmemory", "0")
                    }
                    assertEquals(2, reader.take(java.time.Duration.ofSeconds(10)).orElse(null), "the value the read met stays for the next read")
                    assertEquals(6, double.process(3), "calls work again once Redis has memory")
                }
            }
        }
    }

    private fun oomErrors(admin: Jedis): Long =
        Regex("errorstat_OOM:count=(\\d+)").find(admin.info("errorstats"))?.groupValues?.get(1)?.toLong() ?: 0L

    /** The source "numbers" and the output of the service "keep" that reads it. */
    private fun declare(core: OptimusCore, keep: (Int) -> Unit): Pair<dev.prime.Source<Int>, dev.prime.Source<Int>> {
        val numbers = core.source("numbers", EventBlock<Int>())
        return numbers to numbers.then(core.chain("keep") { x: Int -> keep(x); x })
    }
}

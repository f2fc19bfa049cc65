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
import java.time.Duration

/**
 * A source link whose registration Redis refuses (out of memory) leaves nothing to declare again:
 * after Redis restarts empty, the core re-declares what it has, and no service input that nobody
 * reads is registered with the source (publishes would fill it and fail with QueueFullException).
 */
class FailedSourceLinkTest {

    @Test
    fun aRefusedSourceLinkIsNotDeclaredAgainAfterARedisReset() {
        EmbeddedRedis.start().use { redis ->
            val config = CoreConfig.builder().name("failed-link").build()
            OptimusCore.builder().config(config).redis(redis.uri).leaseTime(Duration.ofSeconds(1))
                .queueLimit(QUEUE_LIMIT).publishTimeout(Duration.ofSeconds(2)).build().use { core ->
                    val numbers = core.source("numbers", EventBlock<Int>())
                    val direct = numbers.reader()
                    val keep = core.chain("keep") { x: Int -> x }
                    core.start()
                    Jedis(URI(redis.uri)).use { admin ->
                        admin.configSet("maxmemory", "1")
                        val refused = assertThrows(PrimeException::class.java) { core.link(numbers, keep) }
                        assertTrue("out of memory" in refused.message!!, refused.message)
                        admin.configSet("maxmemory", "0")
                    }
                    assertEquals(listOf<String>(), core.topology().nodes().map { it.name() }.filter { ">" in it },
                        "the refused link left no node")

                    redis.kill()
                    redis.restart() // empty: the core notices and declares again what it has
                    val deadline = System.nanoTime() + PATIENCE.toNanos()
                    while (core.redisResets() < 1 && System.nanoTime() < deadline) Thread.sleep(10)
                    assertEquals(1L, core.redisResets(), "the reset was noticed")

                    val values = (1..QUEUE_LIMIT * 4).toList()
                    values.forEach { core.publishAll(numbers, listOf(it)) } // QueueFullException if an unread input was registered
                    assertEquals(values, values.map { direct.take(PATIENCE).orElseThrow() })
                }
        }
    }

    private companion object {
        const val QUEUE_LIMIT = 5
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.Token
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.concurrent.CompletableFuture
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * A sync collector's call waits on the collector service's thread in short slices (to learn
 * whether its caller gave up); while that service's Redis is unreachable, the wait rides the outage
 * out, as a wait without slices does: the call gets the next value once Redis is back.
 */
class SyncCollectorOutageTest {

    @Test
    fun aCollectorWaitingForAValueRidesOutAnOutageOfItsService() {
        val config = CoreConfig.builder().name("collector-outage-${System.nanoTime()}").build()
        EmbeddedRedis.start().use { redis ->
            FaultProxy(redis.uri).use { proxy ->
                OptimusCore.builder().config(config).redis(proxy.url).build().use { worker ->
                    worker.syncCollector(worker.source("numbers", EventBlock<Int>())).toBlock() // its service runs here
                    worker.start()
                    OptimusCore.builder().config(config).redis(redis.uri).hosts(emptyList())
                        .callTimeout(Duration.ofSeconds(30)).build().use { caller ->
                            val numbers = caller.source("numbers", EventBlock<Int>())
                            val collect = caller.syncCollector(numbers).toBlock()
                            caller.start()
                            caller.publishAll(numbers, listOf(1))
                            assertEquals(1, collect.process(Token.INSTANCE), "warm: the collector service runs")
                            val call = CompletableFuture.supplyAsync { collect.process(Token.INSTANCE) }
                            val pace = CountDownLatch(1) // never counted down: a bounded pause between looks
                            var looks = 0
                            Jedis(URI(redis.uri)).use { raw ->
                                val processing = caller.keys.serviceProcessing("collect(numbers)")
                                while (raw.llen(processing) == 0L && looks++ < 1000) pace.await(10, TimeUnit.MILLISECONDS)
                                assertEquals(1L, raw.llen(processing), "the collector service took the call and waits for a value")
                            }
                            proxy.refuse() // the collector service's Redis is gone while it waits
                            looks = 0
                            // a few attempts to reconnect: the collector's 50 ms slice has long ended in the outage
                            while (proxy.turnedAway.get() < 3 && looks++ < 1000) pace.await(10, TimeUnit.MILLISECONDS)
                            assertTrue(proxy.turnedAway.get() >= 3, "the worker tried to reach Redis again")
                            proxy.restore()
                            caller.publishAll(numbers, listOf(2))
                            assertEquals(2, call.get(30, TimeUnit.SECONDS), "the waiting call got the next value")
                        }
                }
            }
        }
    }
}

package dev.prime.optimus

import dev.prime.CoreClosedException
import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.conformance.ConformanceBase
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.concurrent.CompletableFuture
import java.util.concurrent.CountDownLatch
import java.util.concurrent.ExecutionException
import java.util.concurrent.Executors
import java.util.concurrent.TimeUnit

/** close() while everything waits on Redis: every waiter ends, no thread or connection is left. */
class CloseTest {

    @Test
    fun closeWakesBlockedServicesReadersAndCallersAndLeavesNothingBehind() {
        val pool = Executors.newFixedThreadPool(2)
        try {
            // a long shutdown timeout: close must not need it
            val config = CoreConfig.builder().shutdownTimeout(Duration.ofSeconds(30)).build()
            val core = OptimusCore.builder().config(config).redis(TestRedis.url).hosts("idle").build()
            val events = EventBlock<Int>()
            core.source(events).then(core.chain("idle") { x: Int -> x })
            val reader = core.source(EventBlock<Int>()).reader()
            val elsewhere = core.chain("elsewhere") { x: Int -> x } // hosted by no process
            core.start()
            val call = elsewhere.toBlock()
            val waiting = CountDownLatch(2)
            val readerResult = CompletableFuture.supplyAsync({ waiting.countDown(); reader.take() }, pool)
            val callResult = CompletableFuture.supplyAsync({ waiting.countDown(); call.process(1) }, pool)
            assertTrue(waiting.await(PATIENCE_S, TimeUnit.SECONDS))
            assertTrue(clientsOf(core.name()) > 0, "the core is connected")

            val started = System.nanoTime()
            core.close()
            val closeTook = Duration.ofNanos(System.nanoTime() - started)

            for (result in listOf(readerResult, callResult)) {
                val e = assertThrows(ExecutionException::class.java) { result.get(PATIENCE_S, TimeUnit.SECONDS) }
                assertTrue(e.cause is CoreClosedException, "blocked calls end with CoreClosedException: ${e.cause}")
            }
            ConformanceBase.assertNoThreadsLeft(core)
            assertEquals(0, clientsOf(core.name()), "connections left behind")
            assertTrue(closeTook < config.shutdownTimeout(), "close took $closeTook")
        } finally {
            pool.shutdownNow()
        }
    }

    @Test
    fun noArgumentCoreOwnsAnEmbeddedRedisAndStopsIt() {
        val core = OptimusCore()
        val url = core.redisUrl
        core.use {
            val twice = it.chain("twice") { x: Int -> 2 * x }
            it.start()
            assertEquals(42, twice.toBlock().process(21))
        }
        val reachable = runCatching { Jedis(URI(url.removeSuffix("/0"))).use { it.ping() } }.isSuccess
        assertFalse(reachable, "the embedded Redis at $url stops with its core")
        ConformanceBase.assertNoThreadsLeft(core)
    }

    private fun clientsOf(core: String): Int = Jedis(URI(TestRedis.url)).use { jedis ->
        jedis.clientList().lines().count { it.contains("name=prime-$core ") || it.contains("name=prime-$core-") }
    }

    private companion object {
        const val PATIENCE_S = 20L
    }
}

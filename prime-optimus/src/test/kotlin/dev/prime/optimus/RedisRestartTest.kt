package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Path
import java.time.Duration
import java.util.concurrent.CompletableFuture
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * Redis crashes (SIGKILL) and comes back mid-stream, with an append-only file synced on every
 * write: services, readers, publishers and callers reconnect, and no accepted value is lost or
 * duplicated.
 */
class RedisRestartTest {

    @Test
    fun servicesReconnectAndNothingAcceptedIsLost(@TempDir dir: Path) {
        val n = 3000
        EmbeddedRedis.builder().appendOnlyDir(dir).start().use { redis ->
            val config = CoreConfig.builder().sourceRetention(n).build()
            OptimusCore.builder().config(config).redis(redis.uri).build().use { core ->
                val events = EventBlock<Int>()
                val doubled = core.source("numbers", events)
                    .then(core.link(core.chain("double") { x: Int -> x * 2 }, core.chain("shift") { x: Int -> x + 1 }))
                    .reader()
                val square = core.chain("square") { x: Int -> x * x }
                core.start()
                val call = square.toBlock()

                val third = CountDownLatch(1)
                val publisher = CompletableFuture.runAsync {
                    for (i in 0 until n) {
                        events.publish(i)
                        if (i == n / 3) third.countDown()
                    }
                }
                val caller = CompletableFuture.supplyAsync {
                    (0 until 300).map { call.process(it) }
                }
                assertTrue(third.await(PATIENCE_S, TimeUnit.SECONDS))
                redis.kill()
                redis.restart()

                val received = (0 until n).map { doubled.take(Duration.ofSeconds(PATIENCE_S)).orElseThrow { AssertionError("value ${it + 1} of $n did not arrive") } }
                assertEquals((0 until n).map { it * 2 + 1 }, received, "every value arrives once, in order")
                assertEquals((0 until 300).map { it * it }, caller.get(PATIENCE_S, TimeUnit.SECONDS))
                publisher.get(PATIENCE_S, TimeUnit.SECONDS)
                assertEquals(java.util.Optional.empty<Int>(), doubled.poll(), "no duplicates")
            }
        }
    }

    private companion object {
        const val PATIENCE_S = 60L
    }
}

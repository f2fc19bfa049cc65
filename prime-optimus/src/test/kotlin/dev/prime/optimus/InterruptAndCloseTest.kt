package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.conformance.ConformanceBase
import dev.prime.liberty.LibertyCore
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.concurrent.CompletableFuture
import java.util.concurrent.CountDownLatch
import java.util.concurrent.ExecutionException
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicReference

/** A blocked take() honours interruption; close() works from a thread of the core itself. */
class InterruptAndCloseTest {

    @Test
    fun anInterruptedTakeThrowsWithinASecondAndLosesNothing() {
        TestRedis.core().use { core ->
            val events = EventBlock<Int>()
            val reader = core.source(events).reader()
            core.start()
            val waiting = CountDownLatch(1)
            val interrupted = AtomicReference<Long>()
            val taker = Thread {
                waiting.countDown()
                try {
                    reader.take()
                } catch (_: InterruptedException) {
                    interrupted.set(System.nanoTime())
                }
            }
            taker.start()
            assertTrue(waiting.await(PATIENCE_S, TimeUnit.SECONDS))
            val sent = System.nanoTime()
            taker.interrupt()
            taker.join(Duration.ofSeconds(PATIENCE_S).toMillis())
            assertFalse(taker.isAlive, "take() ignored the interrupt")
            val took = Duration.ofNanos(interrupted.get() - sent)
            assertTrue(took < Duration.ofMillis(1500), "InterruptedException after $took")

            // a take interrupted while a value is waiting: the value is handed out now or by the next take
            events.publish(42)
            val got = ArrayList<Int>()
            val second = Thread {
                Thread.currentThread().interrupt()
                try {
                    got += reader.take()
                } catch (_: InterruptedException) {
                    // nothing handed out
                }
            }
            second.start()
            second.join(Duration.ofSeconds(PATIENCE_S).toMillis())
            if (got.isEmpty()) got += reader.take(Duration.ofSeconds(PATIENCE_S)).orElseThrow()
            assertEquals(listOf(42), got)
            assertEquals(java.util.Optional.empty<Int>(), reader.poll(), "handed out once")
        }
    }

    @Test
    fun aLibertyServiceReadingAnOptimusSourceStopsWhenItsCoreCloses() {
        TestRedis.core().use { optimus ->
            val events = EventBlock<Int>()
            val source = optimus.source(events)
            optimus.start()
            val liberty = LibertyCore(CoreConfig.builder().shutdownTimeout(Duration.ofSeconds(30)).build())
            val out = liberty.link(source, liberty.chain { x: Int -> x + 1 }).reader()
            liberty.start()
            events.publish(1)
            assertEquals(2, out.take(Duration.ofSeconds(PATIENCE_S)).orElseThrow())
            val started = System.nanoTime()
            liberty.close()
            val took = Duration.ofNanos(System.nanoTime() - started)
            ConformanceBase.assertNoThreadsLeft(liberty)
            assertTrue(took < Duration.ofSeconds(3), "LibertyCore.close() took $took")
        }
    }

    @Test
    fun closeFromAHostedServiceStopsEverythingWithoutWaitingForItself() {
        closeFromOwnThread { core, closeNow ->
            val call = core.chain("closer") { _: Int -> closeNow(); 1 }
            val events = EventBlock<Int>()
            core.source(events).then(call)
            core.start()
            events.publish(1)
        }
    }

    @Test
    fun closeFromAListenerStopsEverythingWithoutWaitingForItself() {
        closeFromOwnThread { core, closeNow ->
            val events = EventBlock<Int>()
            core.source(events).listen { closeNow() }
            core.start()
            events.publish(1)
        }
    }

    /** [setup] makes a core's own thread call `closeNow()`; checks what that close did. */
    private fun closeFromOwnThread(setup: (OptimusCore, () -> Unit) -> Unit) {
        // a long shutdown timeout: close must not wait for its own thread
        val core = OptimusCore(CoreConfig.builder().shutdownTimeout(Duration.ofSeconds(30)).build())
        val url = core.redisUrl
        val outcome = CompletableFuture<Duration>()
        setup(core) {
            val started = System.nanoTime()
            try {
                core.close()
                outcome.complete(Duration.ofNanos(System.nanoTime() - started))
            } catch (e: Throwable) {
                outcome.completeExceptionally(e)
            }
        }
        val took = try {
            outcome.get(60, TimeUnit.SECONDS)
        } catch (e: ExecutionException) {
            throw AssertionError("close() from the core's own thread threw ${e.cause}", e.cause)
        }
        assertTrue(took < Duration.ofSeconds(5), "close() from the core's own thread took $took")
        assertTrue(core.isClosed)
        val reachable = runCatching { Jedis(URI(url.removeSuffix("/0"))).use { it.ping() } }.isSuccess
        assertFalse(reachable, "the embedded Redis at $url stops with its core")
        // the thread that called close() ends once its service returns
        Thread.getAllStackTraces().keys.filter { it.name.startsWith("prime-${core.name()}-") }.forEach { it.join(5000) }
        assertNull(ConformanceBase.threadsOf(core).firstOrNull(), "threads left: ${ConformanceBase.threadsOf(core)}")
    }

    private companion object {
        const val PATIENCE_S = 20L
    }
}

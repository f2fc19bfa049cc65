package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.Reader
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.function.Executable
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Path
import java.time.Duration
import java.util.concurrent.CompletableFuture
import java.util.concurrent.ExecutionException
import java.util.concurrent.TimeUnit

/**
 * Every call with a timeout honours it within timeout + 1 s while Redis is unreachable, killed
 * or behind a frozen network, and gives up with `RedisUnavailableException` (the README's
 * promise for a call, a core's first call included, `take(timeout)`, `poll()` and `drain()`);
 * `poll()` and `drain()` do not wait for a reconnect.
 */
class OutageTimeoutTest {

    @Test
    fun callsAndReadsEndInTimeWhileRedisIsKilled() {
        EmbeddedRedis.start().use { redis ->
            outage(redis.uri, cut = { redis.kill() }, mend = { redis.restart() })
        }
    }

    @Test
    fun callsAndReadsEndInTimeWhileTheNetworkIsFrozen() {
        FaultProxy(TestRedis.url).use { proxy ->
            outage(proxy.url, cut = { proxy.freeze() }, mend = { proxy.thaw() })
        }
    }

    /**
     * A core's first call (and a thread's, when no idle caller's reply list is left) records its
     * reply list before it pushes: that too ends by the call's deadline.
     */
    @Test
    fun aFirstCallEndsInTimeWhileTheNetworkIsFrozen() {
        FaultProxy(TestRedis.url).use { proxy ->
            val config = CoreConfig.builder().name("outage-first-${System.nanoTime()}").build()
            OptimusCore.builder().config(config).redis(proxy.url).callTimeout(CALL_TIMEOUT).build().use { core ->
                val call = core.chain("first") { x: Int -> x }.toBlock()
                core.start()
                proxy.freeze()
                try {
                    val took = timed("a first process", CALL_TIMEOUT) { call.process(1) }
                    println("during the outage: a first process ${took.toMillis()} ms")
                } finally {
                    proxy.thaw()
                }
                assertEquals(2, call.process(2), "works again after the outage")
            }
        }
    }

    /**
     * README: "`take()` waits for Redis to come back" (with its data: an append-only file); and
     * the Reader contract: `poll()` and `drain()` never wait for a reconnect, also while another
     * thread's take of the same reader waits out the outage: they fail at once.
     */
    @Test
    fun anUntimedTakeWaitsThroughAnOutageAndGetsTheValuePublishedAfterIt(@TempDir dir: Path) {
        EmbeddedRedis.builder().appendOnlyDir(dir).start().use { redis ->
            val config = CoreConfig.builder().name("outage-take-${System.nanoTime()}").build()
            OptimusCore.builder().config(config).redis(redis.uri).build().use { core ->
                val events = EventBlock<Int>()
                val reader: Reader<Int> = core.source(events).reader()
                core.start()
                events.publish(1)
                assertEquals(1, reader.take(PATIENCE).orElseThrow())
                redis.kill()
                val taken = CompletableFuture.supplyAsync { reader.take() }
                // while Redis is down the take neither returns nor gives up (longer than poll()'s bound and a few retries)
                assertThrows(java.util.concurrent.TimeoutException::class.java) { taken.get(OUTAGE_MS, TimeUnit.MILLISECONDS) }
                timed("poll while a take of the reader waits out the outage", Duration.ZERO) { reader.poll() }
                timed("drain while a take of the reader waits out the outage", Duration.ZERO) { reader.drain() }
                redis.restart()
                events.publish(2)
                assertEquals(2, taken.get(PATIENCE.toSeconds(), TimeUnit.SECONDS), "the take returns the value published after the outage")
            }
        }
    }

    private fun outage(url: String, cut: () -> Unit, mend: () -> Unit) {
        val config = CoreConfig.builder().name("outage-${System.nanoTime()}").build()
        val core = OptimusCore.builder().config(config).redis(url).callTimeout(CALL_TIMEOUT).build()
        try {
            val call = core.chain("slow") { x: Int -> x }.toBlock()
            val events = EventBlock<Int>()
            val reader: Reader<Int> = core.source(events).reader()
            core.start()
            assertEquals(3, call.process(3), "works before the outage")
            events.publish(1)
            assertEquals(1, reader.take(PATIENCE).orElseThrow())
            cut()

            val callTook = timed("process", CALL_TIMEOUT) { call.process(4) }
            val takeTook = timed("take(timeout)", CALL_TIMEOUT) { reader.take(CALL_TIMEOUT) }
            val pollTook = timed("poll", Duration.ZERO) { reader.poll() }
            val drainTook = timed("drain", Duration.ZERO) { reader.drain() }
            println("during the outage: process ${callTook.toMillis()} ms, take ${takeTook.toMillis()} ms, " +
                "poll ${pollTook.toMillis()} ms, drain ${drainTook.toMillis()} ms")

            mend()
            assertEquals(5, call.process(5), "works again after the outage")
        } finally {
            mend()
            core.close()
        }
    }

    /** Runs [action], which must fail with a RedisUnavailableException within [timeout] + 1 s; returns how long it took. */
    private fun timed(what: String, timeout: Duration, action: Executable): Duration {
        val started = System.nanoTime()
        val future = CompletableFuture.runAsync { action.execute() }
        val bound = timeout.plusSeconds(1)
        val e = try {
            future.get(bound.toMillis() + GRACE_MS, TimeUnit.MILLISECONDS)
            null
        } catch (e: ExecutionException) {
            e.cause
        } catch (_: java.util.concurrent.TimeoutException) {
            throw AssertionError("$what did not end within $bound during the outage")
        }
        val took = Duration.ofNanos(System.nanoTime() - started)
        assertTrue(e is RedisUnavailableException, "$what fails with a RedisUnavailableException during the outage, not $e")
        assertTrue(took <= bound, "$what took $took, more than $bound")
        return took
    }

    private companion object {
        val CALL_TIMEOUT: Duration = Duration.ofSeconds(2)
        val PATIENCE: Duration = Duration.ofSeconds(20)
        const val GRACE_MS = 2000L
        const val OUTAGE_MS = 1500L
    }
}

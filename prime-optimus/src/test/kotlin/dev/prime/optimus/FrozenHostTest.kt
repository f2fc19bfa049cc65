package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.concurrent.TimeUnit
import kotlin.concurrent.thread

/**
 * A host frozen (SIGSTOP) longer than its lease: a successor takes the service over, and when
 * the frozen host resumes (SIGCONT) it finds its lease taken, stops the service and says so; from
 * then on the successor alone hosts it. Nothing is lost or duplicated, neither around the freeze
 * (the step the frozen host was in when it resumes is fenced by the step script: its host lease is
 * the successor's, so it stores nothing, and its values stay in the processing list for the
 * successor) nor afterwards.
 */
class FrozenHostTest {

    @Test
    fun aFrozenHostThatResumesFindsItsServiceTakenOverAndStopsIt() {
        val name = "frozen-host"
        val n = 2000
        EmbeddedRedis.start().use { redis ->
            val config = CoreConfig.builder().name(name).sourceRetention(2 * n).build()
            OptimusCore.builder().config(config).redis(redis.uri).leaseTime(LEASE).hosts(TwoProcessTopology.TEST_SERVICES).build().use { core ->
                val numbers = EventBlock<Int>()
                val output = TwoProcessTopology.declare(core, numbers).output.reader()
                core.start()
                // a host busy in its block (1 ms a value) is almost always in the middle of a step when frozen
                val args = arrayOf(redis.uri, name, LEASE.toMillis().toString(), "host", "1")
                LeaseWorkerMain.declaredHost(*args).use { frozen ->
                    LeaseWorkerMain.startHosting(frozen)
                    LeaseWorkerMain.declaredHost(*args).use { successor ->
                        val received = ArrayList<Int>()
                        val publisher = thread(name = "frozen-host-test-publisher") { (0 until n).forEach(numbers::publish) }
                        try {
                            received += take(output, n / 10)
                            signal("STOP", frozen.pid)
                            LeaseWorkerMain.startHosting(successor)
                            received += take(output, n / 10)
                            signal("CONT", frozen.pid)
                            val stopping = frozen.awaitLineContaining("stops service 'double'", LEASE.seconds + 10)
                            assertTrue(stopping.contains("WARN") && stopping.contains("held by instance"), stopping)
                            frozen.awaitLineContaining("stopped service 'double'", LEASE.seconds + 10)
                        } finally {
                            publisher.join(PATIENCE.toMillis())
                        }
                        // from now on only the successor hosts 'double'
                        (n until 2 * n).forEach(numbers::publish)
                        val bound = 4 * n
                        while (received.size < bound) received += output.take(QUIET).orElse(null) ?: break
                        val whileBoth = (0 until n).map { it * 2 + 1 }
                        val lost = whileBoth.toSet() - received.toSet()
                        val duplicated = received.count { it <= whileBoth.last() } - received.filter { it <= whileBoth.last() }.toSet().size
                        println("FrozenHostTest: around the freeze, lost ${lost.size} and duplicated $duplicated of $n values")
                        assertEquals(0, lost.size, "values published around the freeze lost: ${lost.sorted().take(20)}")
                        assertEquals(0, duplicated, "values published around the freeze duplicated")
                        val afterStop = received.filter { it > whileBoth.last() }
                        val expected = (n until 2 * n).map { it * 2 + 1 }
                        assertTrue(afterStop == expected, "values published after the frozen host stopped: ${expected.size} expected, " +
                            "${afterStop.size} received, ${(expected - afterStop.toSet()).size} lost, ${afterStop.size - afterStop.toSet().size} " +
                            "duplicated, in order: ${afterStop.sorted() == afterStop}")
                    }
                }
            }
        }
    }

    /**
     * The same freeze for a called service whose block takes 100 ms, called by four threads: the
     * frozen host is in its block when frozen, and when it resumes, the step it writes is refused
     * (fenced, or its transaction's WATCH broken) while the blocking take written behind it still
     * runs and moves a request into the successor's processing list. The successor handles that
     * request too: no call is lost (before, it was acknowledged unread and its caller timed out).
     */
    @Test
    fun aFrozenCalledHostThatResumesLosesNoCall() {
        val name = "frozen-called-host"
        EmbeddedRedis.start().use { redis ->
            OptimusCore.builder().config(CoreConfig.builder().name(name).build()).redis(redis.uri).leaseTime(LEASE)
                .callTimeout(CALL_TIMEOUT).hosts(TwoProcessTopology.TEST_SERVICES).build().use { core ->
                    val square = TwoProcessTopology.declare(core, EventBlock()).square
                    core.start()
                    val args = arrayOf(redis.uri, name, LEASE.toMillis().toString(), "host", "0", "100")
                    LeaseWorkerMain.declaredHost(*args).use { frozen ->
                        LeaseWorkerMain.startHosting(frozen)
                        LeaseWorkerMain.declaredHost(*args).use { successor ->
                            val calls = CallersOf(square)
                            try {
                                calls.awaitAnswers(8)
                                signal("STOP", frozen.pid)
                                LeaseWorkerMain.startHosting(successor)
                                calls.awaitAnswers(8)
                                signal("CONT", frozen.pid)
                                frozen.awaitLineContaining("stops service 'square'", LEASE.seconds + 10)
                                calls.awaitAnswers(8)
                            } finally {
                                calls.stop()
                            }
                            println("FrozenHostTest: ${calls.answered.get()} calls answered, ${calls.failed.size} failed")
                            assertEquals(emptyList<String>(), calls.failed.toList(), "calls lost or wrong around the freeze")
                            Jedis(URI(redis.uri)).use { jedis ->
                                assertEquals(0L, jedis.llen(Keys(name).serviceProcessing("square")), "nothing left behind")
                            }
                        }
                    }
                }
        }
    }

    /** [CALLERS] threads calling [square] with numbers of their own until [stop], each call checked. */
    private class CallersOf(private val square: dev.prime.Block<Int, Int>) {
        val answered = java.util.concurrent.atomic.AtomicInteger()
        val failed = java.util.concurrent.ConcurrentLinkedQueue<String>()
        private val answers = java.util.concurrent.LinkedBlockingQueue<Int>()
        @Volatile private var stopped = false
        private val threads = (0 until CALLERS).map { caller ->
            thread(name = "frozen-called-host-caller-$caller") {
                for (k in 0 until CALLS_EACH) {
                    if (stopped) break
                    val x = caller * CALLS_EACH + k
                    try {
                        val y = square.process(x)
                        if (y != x * x) failed += "square($x) answered $y"
                        answered.incrementAndGet()
                        answers += x
                    } catch (e: Exception) {
                        failed += "square($x): $e"
                    }
                }
            }
        }

        /** Waits for [count] more answers (bounded). */
        fun awaitAnswers(count: Int) = repeat(count) {
            checkNotNull(answers.poll(PATIENCE.seconds, TimeUnit.SECONDS)) { "no answer within $PATIENCE; failed: $failed" }
        }

        fun stop() {
            stopped = true
            threads.forEach { it.join(CALL_TIMEOUT.toMillis() + PATIENCE.toMillis()) }
        }
    }

    private fun take(reader: dev.prime.Reader<Int>, count: Int): List<Int> = (0 until count).map { i ->
        reader.take(PATIENCE).orElseThrow { AssertionError("value ${i + 1} of $count did not arrive within $PATIENCE") }
    }

    private fun signal(signal: String, pid: Long) {
        val kill = ProcessBuilder("kill", "-$signal", pid.toString()).inheritIO().start()
        check(kill.waitFor(10, TimeUnit.SECONDS) && kill.exitValue() == 0) { "kill -$signal $pid failed" }
    }

    private companion object {
        val LEASE: Duration = Duration.ofSeconds(1)
        val PATIENCE: Duration = Duration.ofSeconds(20)
        val QUIET: Duration = Duration.ofSeconds(3)
        val CALL_TIMEOUT: Duration = Duration.ofSeconds(10)
        const val CALLERS = 4
        const val CALLS_EACH = 1000
    }
}

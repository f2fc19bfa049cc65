package dev.prime.kotlin

import dev.prime.Block
import dev.prime.ChainFailedException
import dev.prime.CoreConfig
import dev.prime.EventBlock
import kotlinx.coroutines.CancellationException
import kotlinx.coroutines.CompletableDeferred
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.TimeoutCancellationException
import kotlinx.coroutines.async
import kotlinx.coroutines.awaitCancellation
import kotlinx.coroutines.runBlocking
import kotlinx.coroutines.withTimeout
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertInstanceOf
import org.junit.jupiter.api.Assertions.assertSame
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.assertThrows
import java.time.Duration
import java.util.concurrent.ArrayBlockingQueue
import java.util.concurrent.ConcurrentHashMap
import java.util.concurrent.ConcurrentLinkedQueue
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicInteger
import kotlin.coroutines.EmptyCoroutineContext

/**
 * `processSuspending` on one media: a cancelled call (by `withTimeout` or by `cancel()`) ends
 * promptly with the coroutine's cancellation, is abandoned cleanly (its value never reaches a
 * later call), and the calls that actually ran are counted.
 */
internal abstract class SuspendingCallKit(private val media: Media) {

    /** A chain's logic: inputs below zero wait for [release], the others return at once; runs are counted per input. */
    private class Gate {
        val release = CountDownLatch(1)
        val runs = ConcurrentHashMap<Int, AtomicInteger>()
        val started = ConcurrentHashMap<Int, CountDownLatch>()

        fun startedLatch(input: Int): CountDownLatch = started.computeIfAbsent(input) { CountDownLatch(1) }

        fun runs(input: Int): Int = runs[input]?.get() ?: 0

        fun process(input: Int): Int {
            runs.computeIfAbsent(input) { AtomicInteger() }.incrementAndGet()
            startedLatch(input).countDown()
            if (input < 0) check(release.await(WAIT_SECONDS, TimeUnit.SECONDS)) { "never released" }
            return input * 10
        }
    }

    @Test
    fun `a call cut off by withTimeout throws TimeoutCancellationException promptly and the next call gets its own value`() = runBlocking {
        media.newCore().use { core ->
            val gate = Gate()
            val block = core.chain("gated", gate::process).toBlock()
            core.start()
            assertEquals(10, block.processSuspending(1)) // warm: connections, threads, classes

            val began = System.nanoTime()
            assertThrows<TimeoutCancellationException> { runBlocking { withTimeout(50) { block.processSuspending(-1) } } }
            val millis = (System.nanoTime() - began) / 1_000_000
            assertTrue(millis < PROMPT_MILLIS, "the timed-out call ended after $millis ms")

            // the next call, while the abandoned one may still be held by the service, gets its own value
            val next = async(Dispatchers.IO) { block.processSuspending(2) }
            gate.release.countDown()
            assertEquals(20, withTimeout(WAIT_SECONDS * 1000) { next.await() })
            assertEquals(30, block.processSuspending(3))
            assertTrue(gate.runs(-1) <= 1, "the abandoned call ran ${gate.runs(-1)} times")
            assertEquals(1, gate.runs(1))
            assertEquals(1, gate.runs(2))
            assertEquals(1, gate.runs(3))
        }
    }

    @Test
    fun `a call cancelled while its block runs ends at once, and its late value is discarded, not given to the next call`() = runBlocking {
        media.newCore().use { core ->
            val gate = Gate()
            val block = core.chain("gated", gate::process).toBlock()
            core.start()
            val abandoned = async(Dispatchers.IO) { block.processSuspending(-1) }
            assertTrue(gate.startedLatch(-1).await(WAIT_SECONDS, TimeUnit.SECONDS), "the call never reached its block")

            val began = System.nanoTime()
            abandoned.cancel()
            assertThrows<CancellationException> { runBlocking { abandoned.await() } }
            val millis = (System.nanoTime() - began) / 1_000_000
            assertTrue(millis < PROMPT_MILLIS, "the cancelled call ended after $millis ms")

            // Optimus: the service still runs -1; call 2 waits behind it on the same reply list,
            // receives -1's late reply first and must skip it by id
            val next = async(Dispatchers.IO) { block.processSuspending(2) }
            gate.release.countDown()
            assertEquals(20, withTimeout(WAIT_SECONDS * 1000) { next.await() })
            assertEquals(30, block.processSuspending(3))
            assertEquals(1, gate.runs(-1), "the cancelled call's block ran once (it had started)")
            assertEquals(1, gate.runs(2))
            assertEquals(1, gate.runs(3))
        }
    }

    @Test
    fun `a call cancelled before its block ran is withdrawn where calls queue, and never run twice`() = runBlocking {
        media.newCore().use { core ->
            val gate = Gate()
            val block = core.chain("gated", gate::process).toBlock()
            core.start()
            val first = async(Dispatchers.IO) { block.processSuspending(-1) }
            assertTrue(gate.startedLatch(-1).await(WAIT_SECONDS, TimeUnit.SECONDS), "the first call never reached its block")
            val second = async(Dispatchers.IO) { block.processSuspending(-2) } // queued behind -1 where calls queue
            if (!media.callsQueueAtTheService) {
                assertTrue(gate.startedLatch(-2).await(WAIT_SECONDS, TimeUnit.SECONDS), "the second call never ran")
            }
            second.cancel()
            assertThrows<CancellationException> { runBlocking { second.await() } }

            gate.release.countDown()
            assertEquals(-10, withTimeout(WAIT_SECONDS * 1000) { first.await() })
            assertEquals(30, block.processSuspending(3))
            assertEquals(1, gate.runs(-1))
            assertEquals(if (media.callsQueueAtTheService) 0 else 1, gate.runs(-2), "runs of the cancelled call")
            assertEquals(1, gate.runs(3))
        }
    }

    @Test
    fun `a failure of a call that was not cancelled reaches the caller as the media reports it`() = runBlocking {
        media.newCore().use { core ->
            val block = core.chain("negate") { x: Int -> require(x != 0) { "zero" }; -x }.toBlock()
            core.start()
            assertEquals(-7, block.processSuspending(7))
            val failure = assertThrows<ChainFailedException> { runBlocking { block.processSuspending(0) } }
            assertEquals("negate", failure.chainName())
            assertEquals(-8, block.processSuspending(8))
        }
    }

    @Test
    fun `a suspending block runs in a chain and is cancelled when its thread is interrupted`() = runBlocking {
        media.newCore().use { core ->
            val runs = AtomicInteger()
            val release = CompletableDeferred<Unit>()
            val block = core.chain("suspending", suspendingBlock { x: Int ->
                runs.incrementAndGet()
                if (x < 0) withTimeout(WAIT_SECONDS * 1000) { release.await() }
                x + 1
            }).toBlock()
            core.start()
            assertEquals(42, block.processSuspending(41))
            // warm: the first cancellation also starts the coroutines' timer thread
            assertThrows<TimeoutCancellationException> { runBlocking { withTimeout(50) { block.processSuspending(-1) } } }
            val began = System.nanoTime()
            assertThrows<TimeoutCancellationException> { runBlocking { withTimeout(50) { block.processSuspending(-1) } } }
            val millis = (System.nanoTime() - began) / 1_000_000
            assertTrue(millis < PROMPT_MILLIS, "the timed-out call ended after $millis ms")
            release.complete(Unit)
            assertEquals(43, block.processSuspending(42))
            if (media.callsQueueAtTheService) {
                // the first cancelled call held the service (its block is not interrupted there);
                // the second waited behind it and was withdrawn, unless the first was withdrawn too
                assertTrue(runs.get() in 2..3, "runs: ${runs.get()}")
            } else {
                assertEquals(4, runs.get(), "runs: two values and two interrupted calls")
            }
        }
    }

    /**
     * A suspending block whose own `withTimeout` runs out, in a chain called from a coroutine that
     * nobody cancelled: the call fails with the chain's failure (its cause the block's
     * [BlockCancelledException], whose cause is the timeout), so the `launch` that made it fails
     * rather than ending without a word, and the chain takes the next call.
     */
    @Test
    fun `a suspending block's own timeout fails a call that was not cancelled, naming the chain`() = runBlocking {
        media.newCore().use { core ->
            val block = core.chain("times-out", suspendingBlock { x: Int ->
                if (x < 0) withTimeout(1) { awaitCancellation() }
                x + 1
            }).toBlock()
            core.start()
            assertEquals(2, block.processSuspending(1))
            val failure = failureOfLaunch { block.processSuspending(-1) }
            assertInstanceOf(ChainFailedException::class.java, failure, "what the launch failed with")
            assertEquals("times-out", (failure as ChainFailedException).chainName())
            assertInstanceOf(BlockCancelledException::class.java, failure.cause, "the block's failure")
            assertInstanceOf(TimeoutCancellationException::class.java, failure.cause!!.cause, "the logic's timeout")
            assertEquals(3, block.processSuspending(2))
        }
    }

    /**
     * The same in a service: the core's error handler gets the chain's name, the input and the
     * block's [BlockCancelledException], and the service goes on with the next value.
     */
    @Test
    fun `a suspending block's own timeout in a service goes to the error handler and the service goes on`() {
        val failures = ArrayBlockingQueue<Triple<String, Any?, Throwable>>(4)
        val config = CoreConfig.builder().errorHandler { service, input, error -> failures.add(Triple(service, input, error)) }.build()
        media.newCore(config).use { core ->
            val events = EventBlock<Int>()
            val reader = core.source("numbers", events)
                .then(core.chain("times-out", suspendingBlock { x: Int ->
                    if (x < 0) withTimeout(1) { awaitCancellation() }
                    x + 1
                }))
                .reader()
            core.start()
            events.publish(-1)
            events.publish(1)
            assertEquals(2, reader.take(Duration.ofSeconds(WAIT_SECONDS)).orElseThrow(), "the value after the failed one")
            val failure = failures.poll(WAIT_SECONDS, TimeUnit.SECONDS) ?: error("the block's failure never reached the error handler")
            assertEquals("times-out", failure.first)
            assertEquals(-1, failure.second)
            assertInstanceOf(BlockCancelledException::class.java, failure.third, "what the error handler got")
            assertInstanceOf(TimeoutCancellationException::class.java, failure.third.cause, "the logic's timeout")
            assertEquals(null, failures.poll(), "one failure only")
        }
    }

    /**
     * A chain's plain block that lets a cancellation of its own out (a cancelled `Future` it waited
     * for): a call that nobody cancelled fails with the media's [ChainFailedException] naming the
     * chain, whose cause is that very cancellation, so the `launch` that made it fails rather than
     * ending without a word; in a service the error handler gets it with the input, and each goes
     * on with the next value.
     */
    @Test
    fun `a chain's plain block that throws a cancellation of its own fails the call and goes to the error handler`() = runBlocking {
        val own = java.util.concurrent.CancellationException("the block's own: a cancelled Future it waited for")
        val failures = ArrayBlockingQueue<Triple<String, Any?, Throwable>>(4)
        val config = CoreConfig.builder().errorHandler { service, input, error -> failures.add(Triple(service, input, error)) }.build()
        media.newCore(config).use { core ->
            val logic = { x: Int -> if (x < 0) throw own else x + 1 }
            val block = core.chain("cancelling", logic).toBlock()
            val events = EventBlock<Int>()
            val reader = core.source("numbers", events).then(core.chain("cancelling-service", logic)).reader()
            core.start()

            val failure = failureOfLaunch { block.processSuspending(-1) }
            assertInstanceOf(ChainFailedException::class.java, failure, "what the launch failed with")
            assertEquals("cancelling", (failure as ChainFailedException).chainName())
            assertSame(own, failure.cause, "the block's own cancellation")
            assertEquals(3, block.processSuspending(2))

            events.publish(-1)
            events.publish(1)
            assertEquals(2, reader.take(Duration.ofSeconds(WAIT_SECONDS)).orElseThrow(), "the value after the failed one")
            val reported = failures.poll(WAIT_SECONDS, TimeUnit.SECONDS) ?: error("the block's cancellation never reached the error handler")
            assertEquals("cancelling-service", reported.first)
            assertEquals(-1, reported.second)
            assertSame(own, reported.third, "what the error handler got")
            assertEquals(null, failures.poll(), "one failure only")
        }
    }

    /**
     * `processSuspending(input, EmptyCoroutineContext)` runs the block on the caller's thread, and
     * a cancellation still interrupts it there.
     */
    @Test
    fun `with an empty context the call runs on the caller's thread, still interruptibly`() = runBlocking {
        media.newCore().use { core ->
            val gate = Gate()
            val chain = core.chain("gated", gate::process).toBlock()
            val threads = ConcurrentLinkedQueue<Thread>()
            val block = Block<Int, Int> { x -> threads.add(Thread.currentThread()); chain.process(x) }
            core.start()
            assertEquals(10, block.processSuspending(1, EmptyCoroutineContext))
            assertEquals(listOf(Thread.currentThread()), threads.toList(), "the thread the block ran on")

            val began = System.nanoTime()
            assertThrows<TimeoutCancellationException> { runBlocking { withTimeout(50) { block.processSuspending(-1, EmptyCoroutineContext) } } }
            val millis = (System.nanoTime() - began) / 1_000_000
            assertTrue(millis < PROMPT_MILLIS, "the timed-out call ended after $millis ms")
            gate.release.countDown()
            assertEquals(20, block.processSuspending(2, EmptyCoroutineContext))
        }
    }

    /**
     * A chain's block that ignores interrupts: where it runs on the calling thread (Liberty,
     * Radiant) it runs to its end before the cancellation is reported; where the call waits for a
     * service (Optimus) the wait ends at once.
     */
    @Test
    fun `a cancelled call of a block that ignores interrupts ends when the block ends, or at once where calls wait for a service`() = runBlocking {
        media.newCore().use { core ->
            val finished = CountDownLatch(1)
            val deaf = core.chain("deaf") { x: Int ->
                val until = System.nanoTime() + DEAF_MILLIS * 1_000_000
                while (System.nanoTime() < until) Thread.onSpinWait() // ignores interrupts
                if (x == 2) finished.countDown()
                x
            }.toBlock()
            core.start()
            assertEquals(1, deaf.processSuspending(1)) // warm
            val began = System.nanoTime()
            assertThrows<TimeoutCancellationException> { runBlocking { withTimeout(50) { deaf.processSuspending(2) } } }
            val millis = (System.nanoTime() - began) / 1_000_000
            if (media.callsQueueAtTheService) {
                assertTrue(millis < PROMPT_MILLIS, "the cancelled call waited for the service for $millis ms")
            } else {
                assertTrue(millis >= DEAF_MILLIS, "the cancellation was reported after $millis ms, before the block ended")
                assertEquals(0L, finished.count, "the block had ended when the cancellation was reported")
            }
            assertTrue(finished.await(WAIT_SECONDS, TimeUnit.SECONDS), "the block never ended")
        }
    }

    /**
     * A suspending block in a service: closing the core interrupts the service's thread (Liberty
     * and Radiant at once, Optimus once the service has had its shutdown timeout to finish the
     * value), which cancels the block's logic, so the logic is cancelled when `close()` returns.
     */
    @Test
    fun `closing the core cancels a suspending block its service runs`() {
        val running = CountDownLatch(1)
        val cancelled = CountDownLatch(1)
        val timeout = Duration.ofSeconds(2)
        val core = media.newCore(CoreConfig.builder().shutdownTimeout(timeout).build())
        val events = EventBlock<Int>()
        core.source("numbers", events)
            .then(core.chain("waits", suspendingBlock<Int, Int> { awaitCancellationSignalling(running, cancelled) }))
            .reader()
        core.start()
        events.publish(1)
        assertTrue(running.await(WAIT_SECONDS, TimeUnit.SECONDS), "the service never ran the block")
        val began = System.nanoTime()
        core.close()
        val millis = (System.nanoTime() - began) / 1_000_000
        assertTrue(cancelled.await(0, TimeUnit.SECONDS), "close() returned after $millis ms and the block's logic was not cancelled")
        assertTrue(millis < timeout.toMillis() + CLOSE_SLACK_MILLIS, "close() took $millis ms")
    }

    private companion object {
        const val WAIT_SECONDS = 20L

        /** Well under the one-second slices a network wait used to poll in, with room for a loaded machine. */
        const val PROMPT_MILLIS = 750L

        /** How long a block that ignores interrupts spins: well over a cancellation's promptness. */
        const val DEAF_MILLIS = 1_500L

        /** What a close() may take beyond its shutdown timeout on a loaded machine. */
        const val CLOSE_SLACK_MILLIS = 5_000L
    }
}

internal class LibertySuspendingCallTest : SuspendingCallKit(Liberty)

internal class RadiantSuspendingCallTest : SuspendingCallKit(Radiant)

internal class OptimusSuspendingCallTest : SuspendingCallKit(Optimus)

internal class OptimusSlowRedisSuspendingCallTest : SuspendingCallKit(OptimusSlowRedis)

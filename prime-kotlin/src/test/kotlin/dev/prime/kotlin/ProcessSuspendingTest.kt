package dev.prime.kotlin

import dev.prime.Block
import kotlinx.coroutines.CancellationException
import kotlinx.coroutines.CompletableDeferred
import kotlinx.coroutines.CoroutineExceptionHandler
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.SupervisorJob
import kotlinx.coroutines.TimeoutCancellationException
import kotlinx.coroutines.asCoroutineDispatcher
import kotlinx.coroutines.awaitCancellation
import kotlinx.coroutines.cancel
import kotlinx.coroutines.isActive
import kotlinx.coroutines.launch
import kotlinx.coroutines.runBlocking
import kotlinx.coroutines.withTimeout
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertInstanceOf
import org.junit.jupiter.api.Assertions.assertSame
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import kotlin.coroutines.EmptyCoroutineContext

/** `processSuspending` of a plain block, with no core: what its KDoc says of a call that was not cancelled. */
internal class ProcessSuspendingTest {

    /**
     * A block interrupted by something other than the call's cancellation (its own code, an
     * executor shutting down) fails: the call reaches the caller with the block's
     * `InterruptedException`, as the block threw it, not as a cancellation the coroutine never had
     * (which a `launch` would drop without a word).
     */
    @Test
    fun `a block interrupted while its call is not cancelled fails the call with its InterruptedException`(): Unit = runBlocking {
        val interrupted = InterruptedException("the block's own interrupt")
        val block = Block<Int, Int> { throw interrupted }
        for (context in listOf(Dispatchers.IO, EmptyCoroutineContext)) {
            val failure = runCatching { block.processSuspending(1, context) }.exceptionOrNull()
            assertTrue(isActive, "the calling coroutine was cancelled")
            assertInstanceOf(InterruptedException::class.java, failure, "what the call on $context threw")
            assertSame(interrupted, failure, "the block's own exception")
        }
    }

    /**
     * A block that interrupts its own thread and then returns (or throws) leaves no flag on the
     * thread that ran it: the next coroutine that thread runs (a pooled thread's next work) starts
     * without it, as a core's service clears the flag a block set before its next value.
     */
    @Test
    fun `a block that interrupts its own thread leaves no flag on the thread that ran it`() {
        // one thread that runs its tasks as they come and counts the tasks that left its flag set
        // (a pooled thread's next work would start with it), clearing it to go on
        val tasks = java.util.concurrent.LinkedBlockingQueue<Runnable>()
        val flagsLeft = java.util.concurrent.atomic.AtomicInteger()
        val stop = Runnable {}
        val thread = Thread({
            while (true) {
                val task = tasks.poll(WAIT_MILLIS, TimeUnit.MILLISECONDS) ?: break
                if (task === stop) break
                task.run()
                if (Thread.interrupted()) flagsLeft.incrementAndGet()
            }
        }, "kit-one-thread").apply { isDaemon = true; start() }
        val one = java.util.concurrent.Executor { tasks.put(it) }.asCoroutineDispatcher()
        try {
            runBlocking {
                val returns = Block<Int, Int> { x -> Thread.currentThread().interrupt(); x }
                val throws = Block<Int, Int> { Thread.currentThread().interrupt(); throw IllegalStateException("after") }
                assertTrue(returns.processSuspending(7, one) == 7, "the block's value")
                val failure = runCatching { throws.processSuspending(7, one) }.exceptionOrNull()
                assertInstanceOf(IllegalStateException::class.java, failure, "the block's failure")
                kotlinx.coroutines.withContext(one) {} // runs after the calls' tasks on that thread
            }
            assertTrue(flagsLeft.get() == 0, "tasks that left the thread's flag set: ${flagsLeft.get()}")
        } finally {
            tasks.put(stop)
            thread.join(WAIT_MILLIS)
        }
    }

    /** An interrupt the block meets in a blocking wait, not the cancellation's, also fails the call with it. */
    @Test
    fun `a block that meets an interrupt in a wait fails the call with its InterruptedException`(): Unit = runBlocking {
        val block = Block<Int, Int> { x ->
            Thread.currentThread().interrupt()
            Thread.sleep(WAIT_MILLIS)
            x
        }
        val failure = runCatching { block.processSuspending(1) }.exceptionOrNull()
        assertTrue(isActive, "the calling coroutine was cancelled")
        assertInstanceOf(InterruptedException::class.java, failure, "what the call threw")
    }

    /**
     * A block that throws a cancellation of its own while its call is not cancelled (a plain
     * block's `CancellationException`, a suspending block whose `withTimeout` ran out) has failed:
     * the call throws a [BlockCancelledException] whose cause is that cancellation, so a `launch`
     * that made the call fails rather than ending without a word.
     */
    @Test
    fun `a block's own cancellation fails a call that was not cancelled, also in a launch`(): Unit = runBlocking {
        val own = java.util.concurrent.CancellationException("the block's own")
        val plain = Block<Int, Int> { throw own }
        val timingOut = suspendingBlock<Int, Int> { withTimeout(1) { awaitCancellation() } }
        for (context in listOf(Dispatchers.IO, EmptyCoroutineContext)) {
            val failure = failureOfLaunch { plain.processSuspending(1, context) }
            assertInstanceOf(BlockCancelledException::class.java, failure, "what the launch failed with (context $context)")
            assertSame(own, failure!!.cause, "the block's own cancellation")

            val timedOut = failureOfLaunch { timingOut.processSuspending(1, context) }
            assertInstanceOf(BlockCancelledException::class.java, timedOut, "what the launch failed with (context $context)")
            assertInstanceOf(TimeoutCancellationException::class.java, timedOut!!.cause, "the logic's timeout")
        }
    }

    /** A call that is cancelled still ends with the coroutine's cancellation, the block's logic cancelled. */
    @Test
    fun `a cancelled call of a suspending block ends with the coroutine's cancellation`(): Unit = runBlocking {
        val running = CountDownLatch(1)
        val cancelled = CountDownLatch(1)
        val waiting = suspendingBlock<Int, Int> { awaitCancellationSignalling(running, cancelled) }
        for (context in listOf(Dispatchers.IO, EmptyCoroutineContext)) {
            val thrown = runCatching { withTimeout(TIMEOUT_MILLIS) { waiting.processSuspending(1, context) } }.exceptionOrNull()
            assertInstanceOf(TimeoutCancellationException::class.java, thrown, "what the timed-out call threw (context $context)")
        }
        assertTrue(cancelled.await(0, TimeUnit.SECONDS), "the logic was not cancelled")

        val launchedRunning = CountDownLatch(1)
        val launchedCancelled = CountDownLatch(1)
        val launched = suspendingBlock<Int, Int> { awaitCancellationSignalling(launchedRunning, launchedCancelled) }
        val failure = CompletableDeferred<Throwable>()
        val call = launch(Dispatchers.IO) {
            try {
                launched.processSuspending(1)
            } catch (e: Throwable) {
                failure.complete(e)
                throw e
            }
        }
        assertTrue(launchedRunning.await(WAIT_MILLIS, TimeUnit.MILLISECONDS), "the logic never ran")
        call.cancel()
        withTimeout(WAIT_MILLIS) { call.join() }
        assertTrue(launchedCancelled.await(0, TimeUnit.SECONDS), "the launched call's logic was not cancelled")
        val thrown = failure.await()
        assertInstanceOf(CancellationException::class.java, thrown, "what the cancelled call threw")
        assertFalse(thrown is BlockCancelledException, "the caller's cancellation, not the block's failure")
    }

    private companion object {
        const val WAIT_MILLIS = 20_000L
        const val TIMEOUT_MILLIS = 50L
    }
}

/**
 * Runs [call] in a `launch` of its own scope and returns what the launch failed with (what reached
 * its exception handler), or `null` if it ended without a word (normally, or with a cancellation).
 */
internal suspend fun failureOfLaunch(call: suspend () -> Unit): Throwable? {
    val reported = CompletableDeferred<Throwable>()
    val scope = CoroutineScope(SupervisorJob() + Dispatchers.Default + CoroutineExceptionHandler { _, e -> reported.complete(e) })
    try {
        val job = scope.launch { call() }
        withTimeout(20_000L) { job.join() }
        return if (reported.isCompleted) reported.await() else null
    } finally {
        scope.cancel()
    }
}

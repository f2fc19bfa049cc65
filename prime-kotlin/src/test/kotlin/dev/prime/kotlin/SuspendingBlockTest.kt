package dev.prime.kotlin

import kotlinx.coroutines.CancellationException
import kotlinx.coroutines.Job
import kotlinx.coroutines.TimeoutCancellationException
import kotlinx.coroutines.awaitCancellation
import kotlinx.coroutines.withTimeout
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertInstanceOf
import org.junit.jupiter.api.Assertions.assertSame
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicReference

/** `suspendingBlock` as a plain block, with no core: what its KDoc says of a call's thread. */
internal class SuspendingBlockTest {

    /** Interrupting the thread that calls the block cancels the logic, and the call throws `InterruptedException`. */
    @Test
    fun `interrupting the calling thread cancels the logic and the call throws InterruptedException`() {
        val running = CountDownLatch(1)
        val cancelled = CountDownLatch(1)
        val block = suspendingBlock<Int, Int> { awaitCancellationSignalling(running, cancelled) }
        val thrown = AtomicReference<Throwable>()
        val caller = Thread { thrown.set(runCatching { block.process(1) }.exceptionOrNull()) }.apply { isDaemon = true }
        caller.start()
        assertTrue(running.await(WAIT_SECONDS, TimeUnit.SECONDS), "the logic never ran")
        caller.interrupt()
        caller.join(WAIT_SECONDS * 1000)
        assertTrue(!caller.isAlive, "the interrupted call did not end")
        assertTrue(cancelled.await(0, TimeUnit.SECONDS), "the logic was not cancelled")
        assertInstanceOf(InterruptedException::class.java, thrown.get(), "what the call threw")
    }

    /** The calling thread is blocked while the logic runs: the call returns the logic's value. */
    @Test
    fun `each call runs the logic to its end and returns its value`() {
        val threads = mutableListOf<Thread>()
        val block = suspendingBlock { x: Int -> threads += Thread.currentThread(); x * 2 }
        assertTrue(block.process(21) == 42)
        assertTrue(threads == listOf(Thread.currentThread()), "ran on $threads")
    }

    /**
     * Logic whose own `withTimeout` runs out has failed: the call throws a
     * [BlockCancelledException] whose cause is the `TimeoutCancellationException`, not the
     * cancellation itself, which a caller in a coroutine would take for its own.
     */
    @Test
    fun `logic that fails with a cancellation of its own fails the call with BlockCancelledException`() {
        val block = suspendingBlock<Int, Int> { withTimeout(1) { awaitCancellation() } }
        val thrown = runCatching { block.process(1) }.exceptionOrNull()
        assertInstanceOf(BlockCancelledException::class.java, thrown, "what the call threw")
        assertInstanceOf(TimeoutCancellationException::class.java, thrown!!.cause, "its cause")
        assertTrue(thrown.message!!.contains("withTimeout"), thrown.message)

        val own = CancellationException("the logic's own")
        val throwing = suspendingBlock<Int, Int> { throw own }
        assertSame(own, runCatching { throwing.process(1) }.exceptionOrNull()?.cause, "the cause is the very cancellation")
    }

    /** A job the caller put in the context, once cancelled, ends the call with its cancellation. */
    @Test
    fun `a cancelled job in the context ends the call with its cancellation`() {
        val job = Job()
        job.cancel(CancellationException("the caller's job is done"))
        val block = suspendingBlock<Int, Int>(job) { awaitCancellation() }
        val thrown = runCatching { block.process(1) }.exceptionOrNull()
        assertInstanceOf(CancellationException::class.java, thrown, "what the call threw")
        assertFalse(thrown is BlockCancelledException, "not the block's own failure")
    }

    private companion object {
        const val WAIT_SECONDS = 20L
    }
}

/**
 * Suspending logic that counts [running] down, waits until it is cancelled, then counts
 * [cancelled] down and rethrows the cancellation.
 */
internal suspend fun awaitCancellationSignalling(running: CountDownLatch, cancelled: CountDownLatch): Nothing {
    running.countDown()
    try {
        awaitCancellation()
    } catch (e: CancellationException) {
        cancelled.countDown()
        throw e
    }
}

@file:JvmName("SuspendingBlocks")

package dev.prime.kotlin

import dev.prime.Block
import kotlinx.coroutines.CancellationException
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.currentCoroutineContext
import kotlinx.coroutines.ensureActive
import kotlinx.coroutines.runBlocking
import kotlinx.coroutines.runInterruptible
import kotlin.coroutines.CoroutineContext
import kotlin.coroutines.EmptyCoroutineContext

/**
 * Calls this block from a coroutine, on [context] (default [Dispatchers.IO]: a block may wait, and
 * an Optimus chain's block waits for a remote service), and honours cancellation on every media.
 *
 * Cancelling the calling coroutine interrupts the thread that runs the block, and the call ends
 * with the coroutine's [CancellationException] (inside `withTimeout`, a
 * `TimeoutCancellationException`), never with the failure the interrupt caused in the block or the
 * media (such as a `ChainFailedException`). The cancelled call is abandoned cleanly: on Liberty and
 * Radiant the interrupted block returns and its result is dropped; on Optimus the call stops
 * waiting at once, takes its request back if no service took it yet, and the reply of a request a
 * service already took is recognised by its id and discarded, so a later call never receives it.
 *
 * A block that ignores interrupts (a busy loop) and runs on the calling thread (a plain block, a
 * chain's block on Liberty and Radiant) runs to its end before the cancellation is reported; an
 * Optimus chain's call, which waits for the service running the block, stops waiting at once. A
 * failure of a call that was not cancelled reaches the caller as the block's media throws it,
 * also an [InterruptedException] of a block that something else interrupted.
 *
 * @param input the input value
 * @param context where the block runs; [EmptyCoroutineContext] runs it on the caller's thread,
 *     still interruptibly
 * @return the block's output
 */
public suspend fun <I, O> Block<I, O>.processSuspending(
    input: I,
    context: CoroutineContext = Dispatchers.IO,
): O {
    try {
        return runInterruptible(context) {
            try {
                process(input)
            } catch (interrupted: InterruptedException) {
                throw BlockInterrupted(interrupted)
            }
        }
    } catch (cancelled: CancellationException) {
        throw cancelled
    } catch (failure: Throwable) {
        val own = if (failure is BlockInterrupted) failure.interrupted else failure
        // the interrupt of a cancelled call surfaces as whatever the block or the media made of it
        try {
            currentCoroutineContext().ensureActive()
        } catch (cancelled: CancellationException) {
            cancelled.addSuppressed(own)
            throw cancelled
        }
        throw own
    }
}

/**
 * Carries the [InterruptedException] of a call's block out of `runInterruptible`, which turns
 * every one into a cancellation, also when the coroutine was not cancelled (the block's own code
 * or another thread interrupted it): [processSuspending] then rethrows the block's exception.
 */
private class BlockInterrupted(val interrupted: InterruptedException) : RuntimeException(interrupted)

/**
 * A [Block] made of a suspending function, for any core's `chain(...)`: each call runs [logic] to
 * its end on the calling thread (a service thread, or the thread of a synchronous caller), in
 * [context], with the calling thread blocked meanwhile. Interrupting that thread (a core closing
 * its services, a cancelled [processSuspending]) cancels [logic], and the call ends with an
 * [InterruptedException].
 *
 * @param context the coroutine context [logic] runs in; its dispatcher, if any, runs the
 *     suspending parts while the calling thread waits
 * @param logic the block's logic
 * @return a block; thread-safe if [logic] is
 */
public fun <I, O> suspendingBlock(
    context: CoroutineContext = EmptyCoroutineContext,
    logic: suspend (I) -> O,
): Block<I, O> = SuspendingBlock(context, logic)

/** The block of [suspendingBlock]. */
private class SuspendingBlock<I, O>(
    private val context: CoroutineContext,
    private val logic: suspend (I) -> O,
) : Block<I, O> {
    override fun process(input: I): O = runBlocking(context) { logic(input) }

    override fun toString(): String = "SuspendingBlock[$logic]"
}

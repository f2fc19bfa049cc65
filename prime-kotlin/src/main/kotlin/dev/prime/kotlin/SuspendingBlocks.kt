@file:JvmName("SuspendingBlocks")

package dev.prime.kotlin

import dev.prime.Block
import kotlinx.coroutines.CancellationException
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.Job
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
 * also an [InterruptedException] of a block that something else interrupted. A
 * [CancellationException] the block throws while the call is not cancelled (a plain block's own,
 * such as a [suspendingBlock] whose `withTimeout` ran out) is the block's failure, not the
 * call's cancellation: the call throws it as the cause of a [BlockCancelledException], so a
 * caller in a `launch` fails rather than ending without a word. (A chain's block reaches the
 * caller inside the media's `ChainFailedException`, which is no cancellation.) A block that
 * interrupts its own thread leaves no flag on it: the thread that ran the block (a pooled
 * thread, or with [EmptyCoroutineContext] the caller's) goes on with its flag cleared.
 *
 * From Java it is `SuspendingBlocks.processSuspending(block, input, context, continuation)`, which
 * refuses a `null` block or context with a [NullPointerException] naming it and saying what to
 * pass (Kotlin callers cannot pass one).
 *
 * @param input the input value
 * @param context where the block runs; [EmptyCoroutineContext] runs it on the caller's thread,
 *     still interruptibly
 * @return the block's output
 */
@JvmSynthetic // Java calls processSuspendingFromJava, under the name processSuspending
@JvmName("processSuspendingOfBlock")
public suspend fun <I, O> Block<I, O>.processSuspending(
    input: I,
    context: CoroutineContext = Dispatchers.IO,
): O {
    try {
        return runInterruptible(context) {
            try {
                process(input)
            } catch (interrupted: InterruptedException) {
                throw CarriedOut(interrupted)
            } catch (cancelled: CancellationException) {
                throw CarriedOut(cancelled)
            } finally {
                // a flag the block set on its own thread stays with the block: the thread (a pooled
                // one's next work) goes on without it, as a core's service clears it before its next
                // value; a cancellation's own interrupt is recorded in the job, not in the flag
                Thread.interrupted()
            }
        }
    } catch (cancelled: CancellationException) {
        throw cancelled // the call's cancellation: the block's own are carried out
    } catch (failure: Throwable) {
        val own = if (failure is CarriedOut) failure.thrown else failure
        // the interrupt of a cancelled call surfaces as whatever the block or the media made of it
        try {
            currentCoroutineContext().ensureActive()
        } catch (cancelled: CancellationException) {
            cancelled.addSuppressed(own)
            throw cancelled
        }
        throw if (own is CancellationException) BlockCancelledException(own) else own
    }
}

/**
 * [processSuspending] as Java sees it, `SuspendingBlocks.processSuspending(block, input, context,
 * continuation)`: internal, so not part of the Kotlin API, and with nullable parameters, so that a
 * `null` from Java is refused here, naming the parameter and what to pass, at once (Kotlin makes
 * no check of a suspending function's receiver: the null would fail later, in the block's call,
 * with a bare [NullPointerException] given to the continuation).
 */
@JvmName("processSuspending")
internal suspend fun <I, O> processSuspendingFromJava(block: Block<I, O>?, input: I, context: CoroutineContext?): O {
    if (block == null) {
        throw NullPointerException(
            "SuspendingBlocks.processSuspending(block, input, context, continuation): block must not be null; " +
                "pass the Block to call",
        )
    }
    if (context == null) {
        throw NullPointerException(
            "SuspendingBlocks.processSuspending(block, input, context, continuation): context must not be null; " +
                "pass where the block runs, such as Dispatchers.IO (EmptyCoroutineContext for the caller's thread)",
        )
    }
    return block.processSuspending(input, context)
}

/**
 * Carries what a call's block threw out of `runInterruptible` when it would pass for the call's
 * cancellation there: an [InterruptedException], which `runInterruptible` turns into a
 * cancellation, and a [CancellationException], both also when the coroutine was not cancelled
 * (the block's own code or another thread interrupted it; the block's own timeout ran out).
 * [processSuspending] then tells the two cases apart, with the very object the block threw.
 */
private class CarriedOut(val thrown: Exception) : RuntimeException(thrown)

/**
 * A [Block] made of a suspending function, for any core's `chain(...)`: each call runs [logic] to
 * its end on the calling thread (a service thread, or the thread of a synchronous caller), in
 * [context], with the calling thread blocked meanwhile. Interrupting that thread (a core closing
 * its services, a cancelled [processSuspending]) cancels [logic], and the call ends with an
 * [InterruptedException].
 *
 * A [CancellationException] that [logic] throws of its own (a `withTimeout` in it that ran out)
 * is the block's failure: the call throws a [BlockCancelledException] whose cause it is, never
 * the cancellation itself, which a caller running in a coroutine would take for its own and drop
 * without a word. A chain's synchronous caller gets it inside the media's `ChainFailedException`,
 * and a service gives it to the core's error handler, as any failure of a block. Only when a
 * `Job` in [context] was cancelled does the call end with that job's [CancellationException].
 *
 * From Java it is `SuspendingBlocks.suspendingBlock(context, logic)`, which refuses a `null`
 * context or logic with a [NullPointerException] naming it and saying what to pass, as the core's
 * declarations refuse a `null` (Kotlin callers cannot pass one).
 *
 * @param context the coroutine context [logic] runs in; its dispatcher, if any, runs the
 *     suspending parts while the calling thread waits
 * @param logic the block's logic
 * @return a block; thread-safe if [logic] is
 */
@JvmSynthetic // Java calls suspendingBlockFromJava, under the name suspendingBlock
@JvmName("suspendingBlockOf")
public fun <I, O> suspendingBlock(
    context: CoroutineContext = EmptyCoroutineContext,
    logic: suspend (I) -> O,
): Block<I, O> = SuspendingBlock(context, logic)

/**
 * [suspendingBlock] as Java sees it, `SuspendingBlocks.suspendingBlock(context, logic)`: internal,
 * so not part of the Kotlin API, and with nullable parameters, so that a `null` from Java is
 * refused by the checks here, naming the parameter and what to pass, not by the check Kotlin makes
 * of a non-null parameter.
 */
@JvmName("suspendingBlock")
internal fun <I, O> suspendingBlockFromJava(context: CoroutineContext?, logic: (suspend (I) -> O)?): Block<I, O> {
    if (context == null) {
        throw NullPointerException(
            "SuspendingBlocks.suspendingBlock(context, logic): context must not be null; pass the coroutine " +
                "context the logic runs in (EmptyCoroutineContext for none)",
        )
    }
    if (logic == null) {
        throw NullPointerException(
            "SuspendingBlocks.suspendingBlock(context, logic): logic must not be null; pass the suspending " +
                "function the block runs for each input",
        )
    }
    return SuspendingBlock(context, logic)
}

/** The block of [suspendingBlock]. */
private class SuspendingBlock<I, O>(
    private val context: CoroutineContext,
    private val logic: suspend (I) -> O,
) : Block<I, O> {
    override fun process(input: I): O = try {
        runBlocking(context) { logic(input) }
    } catch (cancelled: CancellationException) {
        if (context[Job]?.isActive == false) {
            throw cancelled // the job the caller gave in the context was cancelled
        }
        throw BlockCancelledException(cancelled) // the logic's own (an interrupt ends it with InterruptedException)
    }

    override fun toString(): String = "SuspendingBlock[$logic]"
}

package dev.prime.kotlin

import kotlinx.coroutines.CancellationException

/**
 * A block failed with a cancellation of its own while nothing cancelled its caller: typically a
 * `withTimeout` inside a [suspendingBlock] that ran out (a `TimeoutCancellationException`), or a
 * plain block that let a `java.util.concurrent.CancellationException` out (a cancelled `Future`
 * it waited for). The [cause] is that cancellation, the very object.
 *
 * Such a cancellation is a failure of the block, not of the caller: passed on as a
 * [CancellationException], a coroutine that called the block (a `launch`, a flow) would take it
 * for its own cancellation and end without a word, and the failure would be lost. So
 * [suspendingBlock] and [processSuspending] throw it as this exception, which reaches a
 * synchronous caller (inside a chain's `ChainFailedException`) and a core's error handler as any
 * other failure does. To handle a timeout inside the block, catch the
 * `TimeoutCancellationException` there or use `withTimeoutOrNull`.
 */
public class BlockCancelledException internal constructor(
    cause: CancellationException,
) : RuntimeException(
    "the block failed with a cancellation of its own while its caller was not cancelled ($cause), such as" +
        " a withTimeout inside it that ran out; it is the block's failure: catch the cancellation inside" +
        " the block (or use withTimeoutOrNull) to handle it there",
    cause,
) {
    /** The block's own cancellation, the very object. */
    override val cause: CancellationException get() = super.cause as CancellationException

    private companion object {
        private const val serialVersionUID: Long = 1L
    }
}

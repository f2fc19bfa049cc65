@file:JvmName("PrimeCoroutines")

package dev.prime.optimus

import dev.prime.Block
import dev.prime.Source
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.flow.Flow
import kotlinx.coroutines.flow.flow
import kotlinx.coroutines.flow.flowOn
import kotlinx.coroutines.runInterruptible
import java.time.Duration

/**
 * Calls this block from a coroutine without blocking the caller's thread: the call runs on
 * [Dispatchers.IO] (an Optimus chain's block waits for a remote service). Cancelling the
 * coroutine interrupts a block that waits interruptibly; a remote call ends at the latest when its
 * core closes.
 */
public suspend fun <I, O> Block<I, O>.processSuspending(input: I): O =
    runInterruptible(Dispatchers.IO) { process(input) }

/**
 * The values of this source as a cold [Flow]: each collection creates a new reader (which starts
 * at the oldest retained value) and emits every value until the collector stops or the core
 * closes (then the flow fails with [dev.prime.CoreClosedException]). Waiting happens on
 * [Dispatchers.IO], in steps of at most [pollEvery] so that cancellation is noticed promptly.
 */
public fun <T> Source<T>.asFlow(pollEvery: Duration = Duration.ofMillis(200)): Flow<T> {
    require(!pollEvery.isNegative && !pollEvery.isZero) { "pollEvery must be positive, was $pollEvery" }
    return flow {
        val reader = reader()
        while (true) {
            val next = runInterruptible { reader.take(pollEvery) }
            if (next.isPresent) emit(next.get())
        }
    }.flowOn(Dispatchers.IO)
}

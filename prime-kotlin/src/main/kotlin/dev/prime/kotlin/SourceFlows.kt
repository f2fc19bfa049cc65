@file:JvmName("SourceFlows")

package dev.prime.kotlin

import dev.prime.CoreClosedException
import dev.prime.Reader
import dev.prime.Source
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.currentCoroutineContext
import kotlinx.coroutines.ensureActive
import kotlinx.coroutines.flow.Flow
import kotlinx.coroutines.flow.flow
import kotlinx.coroutines.flow.flowOn
import kotlinx.coroutines.runInterruptible

/**
 * The values of this source as a cold [Flow]. Each collection makes a new reader, which starts at
 * the oldest value the source retains, and emits every value in order; the flow completes
 * normally when the source's core closes (also if it was closed before the collection began).
 * Values the core still held for the reader when it closed are not emitted. A collection begun
 * before the core's `start()` reads as the media's readers do then: on Liberty and Radiant it
 * waits for the start and emits from it; Optimus refuses a read before `start()`, so there the
 * collection fails at once with that `IllegalStateException`.
 *
 * The reader waits in a blocking `take()` on [Dispatchers.IO], without polling; cancelling the
 * collector interrupts that wait (Liberty and Radiant wake at once, a network media within its
 * documented bound) and closes the reader, so the source stops keeping values for it. The flow
 * is buffered between the reader's thread and the collector like any `flowOn` flow; apply
 * `buffer(...)` or `conflate()` to choose how.
 *
 * Only the collector's cancellation and the core's close end the wait. An interrupt that is not
 * the collector's cancellation (an interrupt flag that other code left set on the pooled thread
 * the reader waits on) is nobody's request to this flow, and the collector could do nothing
 * about it: the take it ends is retried (the interrupted take cleared the flag, and a value it
 * did not hand out stays for the next one, as `Reader.take()` promises), so no value is lost and
 * the flow does not end as if cancelled, which in a `launch` would end the collection without a
 * word.
 *
 * From Java it is `SourceFlows.asFlow(source)`, which refuses a `null` source with a
 * [NullPointerException] naming it and saying what to pass, as the core's declarations refuse a
 * `null` (Kotlin callers cannot pass one).
 *
 * @return a flow of this source's values
 */
@JvmSynthetic // Java calls asFlowFromJava, under the name asFlow
@JvmName("asFlowOfSource")
public fun <T> Source<T>.asFlow(): Flow<T> = flow {
    val reader = try {
        reader()
    } catch (_: CoreClosedException) {
        return@flow
    }
    reader.use {
        while (true) {
            val next = try {
                runInterruptible { takeOrInterrupted(reader) }
            } catch (_: CoreClosedException) {
                return@flow
            }
            if (next === Interrupted) {
                currentCoroutineContext().ensureActive() // the collector's cancellation interrupted the take
                continue // an interrupt that was not the collector's: take again
            }
            @Suppress("UNCHECKED_CAST")
            emit(next as T)
        }
    }
}.flowOn(Dispatchers.IO)

/**
 * [asFlow] as Java sees it, `SourceFlows.asFlow(source)`: internal, so not part of the Kotlin API,
 * and with a nullable parameter, so that a `null` from Java is refused by the check here, naming
 * the parameter, not by the check Kotlin makes of a non-null parameter (which names it `<this>`).
 */
@JvmName("asFlow")
internal fun <T> asFlowFromJava(source: Source<T>?): Flow<T> {
    if (source == null) {
        throw NullPointerException(
            "SourceFlows.asFlow(source): source must not be null; pass the Source whose values the flow " +
                "emits (one that core.source(...) or a chain's reader made)",
        )
    }
    return source.asFlow()
}

/**
 * The reader's next value, or [Interrupted] if an interrupt ended the take: `runInterruptible`
 * would turn the [InterruptedException] into a cancellation whatever interrupted the thread, and
 * only the collector's own cancellation may end the flow that way.
 */
private fun takeOrInterrupted(reader: Reader<*>): Any? = try {
    reader.take()
} catch (_: InterruptedException) {
    Interrupted
}

/** What [takeOrInterrupted] returns for a take an interrupt ended (a reader never returns it). */
private object Interrupted

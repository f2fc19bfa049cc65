@file:JvmName("SourceFlows")

package dev.prime.kotlin

import dev.prime.CoreClosedException
import dev.prime.Source
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.flow.Flow
import kotlinx.coroutines.flow.flow
import kotlinx.coroutines.flow.flowOn
import kotlinx.coroutines.runInterruptible

/**
 * The values of this source as a cold [Flow]. Each collection makes a new reader, which starts at
 * the oldest value the source retains, and emits every value in order; the flow completes
 * normally when the source's core closes (also if it was closed before the collection began).
 * Values the core still held for the reader when it closed are not emitted.
 *
 * The reader waits in a blocking `take()` on [Dispatchers.IO], without polling; cancelling the
 * collector interrupts that wait (Liberty and Radiant wake at once, a network media within its
 * documented bound) and closes the reader, so the source stops keeping values for it. The flow
 * is buffered between the reader's thread and the collector like any `flowOn` flow; apply
 * `buffer(...)` or `conflate()` to choose how.
 *
 * @return a flow of this source's values
 */
public fun <T> Source<T>.asFlow(): Flow<T> = flow {
    val reader = try {
        reader()
    } catch (_: CoreClosedException) {
        return@flow
    }
    reader.use {
        while (true) {
            val next = try {
                runInterruptible { reader.take() }
            } catch (_: CoreClosedException) {
                return@flow
            }
            emit(next)
        }
    }
}.flowOn(Dispatchers.IO)

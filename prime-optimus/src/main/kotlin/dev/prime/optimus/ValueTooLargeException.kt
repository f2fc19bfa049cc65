package dev.prime.optimus

import dev.prime.PrimeException

/**
 * A value encodes to more bytes than the core allows ([OptimusCore.Builder.maxValueBytes]); it
 * was refused before anything was sent, at the publish or call that gave it. The message names
 * the type, its size and the limit.
 */
public class ValueTooLargeException internal constructor(message: String) : PrimeException(message) {
    private companion object {
        private const val serialVersionUID: Long = 1L
    }
}

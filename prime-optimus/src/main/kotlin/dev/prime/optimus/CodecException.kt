package dev.prime.optimus

import dev.prime.PrimeException

/** Bytes from Redis could not, or must not, be decoded; the message says why. */
public class CodecException(message: String, cause: Throwable? = null) : PrimeException(message, cause) {
    private companion object {
        private const val serialVersionUID: Long = 1L
    }
}

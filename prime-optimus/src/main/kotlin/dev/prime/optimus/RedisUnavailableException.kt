package dev.prime.optimus

import dev.prime.PrimeException

/**
 * Redis could not be reached (or kept failing with a transient error) for longer than the
 * operation allowed: a call's timeout, a publish's bound. The message names the operation, how
 * long it waited and the last error; nothing of the operation is known to have taken effect
 * unless the message says so.
 */
public class RedisUnavailableException(message: String, cause: Throwable? = null) : PrimeException(message, cause) {
    private companion object {
        private const val serialVersionUID: Long = 1L
    }
}

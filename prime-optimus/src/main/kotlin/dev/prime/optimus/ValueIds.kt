package dev.prime.optimus

import java.security.SecureRandom
import java.util.concurrent.atomic.AtomicLong

/**
 * Ids of values: a random 64-bit start per core plus a counter, so ids of different processes
 * do not meet in practice; the values a service makes of one input get ids derived from it.
 */
internal class ValueIds {
    private val counter = AtomicLong(SecureRandom().nextLong())

    fun next(): Long = counter.incrementAndGet()

    companion object {
        /** The id of the [index]-th value made of the value [id] (a mixing function, not a counter). */
        fun derive(id: Long, index: Int): Long {
            var x = id + (index + 1) * -0x61c8864680b583ebL
            x = (x xor (x ushr 33)) * -0xae502812aa7333L
            x = (x xor (x ushr 33)) * -0x3b314601e57a13adL
            return x xor (x ushr 33)
        }
    }
}

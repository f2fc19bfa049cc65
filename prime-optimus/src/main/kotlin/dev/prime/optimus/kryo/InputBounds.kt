package dev.prime.optimus.kryo

import com.esotericsoftware.kryo.io.Input

/**
 * Refuses a length prefix that the rest of the bytes cannot hold, before anything is allocated
 * for it: [count] items of at least [minBytesEach] bytes each must fit in what remains of the
 * (array-backed) input. This is what keeps a crafted "2 billion elements" prefix from costing
 * gigabytes of heap.
 */
internal fun Input.requireAvailable(count: Int, minBytesEach: Int, what: String) {
    val remaining = limit() - position()
    if (count < 0) {
        throw RefusedBytesException("$what claims a negative length ($count)")
    }
    if (count.toLong() * minBytesEach > remaining) {
        throw RefusedBytesException(
            "$what claims $count elements (at least ${count.toLong() * minBytesEach} bytes), " +
                "but only $remaining bytes remain",
        )
    }
}

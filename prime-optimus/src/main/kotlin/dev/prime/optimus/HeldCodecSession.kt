package dev.prime.optimus

import dev.prime.optimus.kryo.KryoSession

/**
 * A [KryoCodec] session kept by one user across many values: a service for its whole run, a
 * reader for its life, a `publishAll` for its batch. Each value then costs no pool operation,
 * where [KryoCodec.encode] and [KryoCodec.decode] take a session from the pool and give it back
 * for every value (an atomic exchange and a compare-and-set each: a tenth of the Java time of a
 * flow's threads, in a profile of one hop).
 *
 * Design note. Not thread-safe: the user calls it from one thread at a time, with a
 * happens-before edge between two threads that take turns (a coroutine's dispatch, a reader's
 * turn lock). The session is taken from the pool at first use and held from then on; while a
 * value is encoded or decoded the holder does not hold it, so a failure, which leaves a Kryo in
 * an unknown state, drops it (the next value takes a fresh one), and a nested use (a block that
 * calls a chain from inside a service's batch) goes to the pool as any other call does. [close]
 * gives it back to the pool; a holder that is never closed leaves its session to the garbage
 * collector.
 */
internal class HeldCodecSession(private val codec: KryoCodec) : AutoCloseable {
    private var session: KryoSession? = null

    /** [KryoCodec.encode] after [room] zero bytes. */
    fun encode(value: Any, room: Int): ByteArray {
        val using = take()
        val bytes = codec.encodeWith(using, value, room)
        session = using
        return bytes
    }

    /** [KryoCodec.decode] of the [length] bytes of [bytes] from [offset], read in place. */
    fun decode(bytes: ByteArray, offset: Int, length: Int): Any {
        val using = take()
        val value = codec.decodeWith(using, bytes, offset, length)
        session = using
        return value
    }

    private fun take(): KryoSession {
        val held = session ?: return codec.obtain()
        session = null
        return held
    }

    /** Gives the session back to the codec's pool; a later use takes one again. */
    override fun close() {
        session?.let(codec::free)
        session = null
    }
}

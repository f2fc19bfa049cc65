package dev.prime.optimus

import dev.prime.optimus.kryo.KryoSession

/**
 * A [KryoCodec] session kept by one user across many values: a service for its whole run, a
 * reader for its life, a `publishAll` for its batch. Each value then costs no pool operation,
 * where [KryoCodec.encode] and [KryoCodec.decode] take a session from the pool and give it back
 * for every value (an atomic exchange and a compare-and-set: about 20 ns a value in
 * `SharedCodecBenchmark`, four times per value through one hop of a flow).
 *
 * Design note. Not thread-safe: the user calls it from one thread at a time, with a
 * happens-before edge between two threads that take turns (a coroutine's dispatch, a reader's
 * turn lock). The session is taken from the pool at first use and held from then on. A value's
 * encode or decode only reads the holder's field: a core makes its services' holders one after
 * another, so holders used on different cores may share a cache line, and a write per value would
 * move that line between the cores (in `SharedCodecBenchmark`, two threads whose holders wrote
 * their field twice per value took 150–180 ns a round trip, against 74 ns for one thread). A
 * failure, which leaves a Kryo in an unknown state, drops the session (the next value takes a
 * fresh one). Not reentrant, and it need not be: nothing that runs inside an encode or a decode
 * can reach its holder (a block that calls a chain runs between values, and its call goes to the
 * pool). [close] gives the session back to the pool; a holder that is never closed leaves it to
 * the garbage collector.
 */
internal class HeldCodecSession(private val codec: KryoCodec) : AutoCloseable {
    private var session: KryoSession? = null

    /** [KryoCodec.encode] after [room] zero bytes. */
    fun encode(value: Any, room: Int): ByteArray = withSession { codec.encodeWith(it, value, room) }

    /** [KryoCodec.decode] of the [length] bytes of [bytes] from [offset], read in place. */
    fun decode(bytes: ByteArray, offset: Int, length: Int): Any = withSession { codec.decodeWith(it, bytes, offset, length) }

    /** Runs [action] with the held session (taken at first use); a failure drops the session. */
    private inline fun <R> withSession(action: (KryoSession) -> R): R {
        val using = session ?: codec.obtain().also { session = it }
        try {
            return action(using)
        } catch (e: Throwable) {
            session = null
            throw e
        }
    }

    /** Gives the session back to the codec's pool; a later use takes one again. */
    override fun close() {
        session?.let(codec::free)
        session = null
    }
}

package dev.prime.optimus.kryo

import com.esotericsoftware.kryo.Kryo
import com.esotericsoftware.kryo.Registration
import com.esotericsoftware.kryo.io.Output
import java.util.concurrent.ConcurrentLinkedQueue
import java.util.concurrent.atomic.AtomicInteger

/**
 * One [Kryo] with its reusable output and input buffers. Used by one thread at a time: taken
 * from a [KryoSessionPool], used for one encode or decode, and given back (or dropped, if the
 * call failed and left it in an unknown state).
 *
 * Memory: the output buffer grows to the largest value encoded and is replaced by a small one
 * when it exceeds [RETAINED_OUTPUT_BYTES]; the input keeps no reference to the bytes it read.
 */
internal class KryoSession(private val kryo: Kryo) {
    private val output = Output(INITIAL_OUTPUT_BYTES, -1)
    private val input = BoundedInput()

    /** Class id and value; a copy of exactly the written bytes. */
    fun encode(value: Any): ByteArray {
        output.reset()
        kryo.writeClassAndObject(output, value)
        val bytes = output.toBytes()
        if (output.buffer.size > RETAINED_OUTPUT_BYTES) output.setBuffer(ByteArray(INITIAL_OUTPUT_BYTES), -1)
        return bytes
    }

    /**
     * The registration a value of exactly [type] is written under, admitting the type if a lazy
     * rule allows it.
     *
     * @throws UnregisteredTypeException if the codec does not allow [type]
     */
    fun registration(type: Class<*>): Registration = kryo.getRegistration(type)

    /**
     * The value [bytes] hold, or null if they hold Kryo's null marker.
     *
     * @throws RefusedBytesException if bytes are left over after the value
     */
    fun decode(bytes: ByteArray): Any? {
        input.setBuffer(bytes)
        try {
            val value: Any? = kryo.readClassAndObject(input)
            val left = input.limit() - input.position()
            if (left != 0) throw RefusedBytesException("$left bytes are left over after the value")
            return value
        } finally {
            input.release()
        }
    }

    private companion object {
        private const val INITIAL_OUTPUT_BYTES = 512
        private const val RETAINED_OUTPUT_BYTES = 64 * 1024
    }
}

/**
 * Thread-safe pool of [KryoSession]s over one [KryoRegistry]. Threads that find it empty create a
 * session; at most [capacity] idle sessions are kept, the rest are left to the garbage collector.
 *
 * Design note. Every encode and decode of a core takes a session and gives it back, from the
 * publishing thread, every service and every reader at once, so the pool is lock-free (a
 * [ConcurrentLinkedQueue]; Kryo's own thread-safe pool takes a lock per call, and that lock was
 * the most sampled frame of a busy Optimus flow). The idle count may briefly pass [capacity] by
 * the number of threads freeing at the same moment; it only bounds memory.
 */
internal class KryoSessionPool(private val registry: KryoRegistry, private val capacity: Int) {
    private val idle = ConcurrentLinkedQueue<KryoSession>()
    private val idleCount = AtomicInteger()

    /** An idle session, or a new one. */
    fun obtain(): KryoSession {
        val session = idle.poll() ?: return KryoSession(registry.newKryo())
        idleCount.decrementAndGet()
        return session
    }

    /** Gives [session] back for another call (dropped if [capacity] sessions are idle already). */
    fun free(session: KryoSession) {
        if (idleCount.get() >= capacity) return
        idleCount.incrementAndGet()
        idle.offer(session)
    }
}

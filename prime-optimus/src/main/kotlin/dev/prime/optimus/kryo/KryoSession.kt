package dev.prime.optimus.kryo

import com.esotericsoftware.kryo.Kryo
import com.esotericsoftware.kryo.Registration
import com.esotericsoftware.kryo.io.Output
import java.util.concurrent.ConcurrentLinkedQueue
import java.util.concurrent.atomic.AtomicInteger
import java.util.concurrent.atomic.AtomicReferenceArray

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

    /** Class id and value, after [room] zero bytes; a copy of exactly the bytes written. */
    fun encode(value: Any, room: Int = 0): ByteArray {
        output.reset()
        repeat(room) { output.writeByte(0) }
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
     * The value the [length] bytes of [bytes] from [offset] hold, or null if they hold Kryo's null
     * marker. The bytes are read where they lie.
     *
     * @throws RefusedBytesException if bytes are left over after the value
     */
    fun decode(bytes: ByteArray, offset: Int = 0, length: Int = bytes.size): Any? {
        input.setBuffer(bytes, offset, length)
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
 * session; at most one session per slot and [capacity] more are kept idle, the rest are left to
 * the garbage collector.
 *
 * Design note. Every encode and decode of a core takes a session and gives it back, from the
 * publishing thread, every service and every reader at once, so the pool must cost nothing when
 * threads use it together. A single queue shared by all threads (the pool's first form, a
 * `ConcurrentLinkedQueue`) moved its head, its tail and its count between the cores on every call:
 * with two threads round-tripping a 100 B value through one codec, a round trip took 7× as long as
 * with a codec per thread (`SharedCodecBenchmark`). So each thread first uses a slot of its own:
 * the thread's id, mixed, picks one of a few slots (four per processor, 16 to 64), each on a
 * cache line of its own, and a thread that takes its session back from its slot and returns it
 * there touches only a line its core already holds. Taking is one `getAndSet(null)`, so a session is handed to one thread only;
 * giving back is one `compareAndSet(null, session)`. Threads whose hashes share a slot still get a
 * session each: what one finds taken or occupied goes through the shared queue behind the slots,
 * whose idle count may briefly pass [capacity] by the number of threads freeing at the same
 * moment (it only bounds memory). Nothing ties a session to a thread: a thread that ends leaves its
 * slot's session to the next thread hashed there.
 */
internal class KryoSessionPool(
    private val registry: KryoRegistry,
    private val capacity: Int,
    /** Slots for threads: a power of two, 1 to 2^16. */
    slots: Int = slotsFor(Runtime.getRuntime().availableProcessors()),
) {
    private val slotShift: Int
    private val slots: AtomicReferenceArray<KryoSession?>
    private val spare = ConcurrentLinkedQueue<KryoSession>()
    private val spareCount = AtomicInteger()

    init {
        require(slots in 1..(1 shl 16) && Integer.bitCount(slots) == 1) { "slots must be a power of two from 1 to 65536, not $slots" }
        slotShift = 32 - Integer.numberOfTrailingZeros(slots)
        this.slots = AtomicReferenceArray(slots * STRIDE)
    }

    /** An idle session, or a new one. */
    fun obtain(): KryoSession {
        slots.getAndSet(slotOfThisThread(), null)?.let { return it }
        val session = spare.poll() ?: return KryoSession(registry.newKryo())
        spareCount.decrementAndGet()
        return session
    }

    /** Gives [session] back for another call (dropped if its slot and [capacity] spare places are taken). */
    fun free(session: KryoSession) {
        val slot = slotOfThisThread()
        if (slots.get(slot) == null && slots.compareAndSet(slot, null, session)) return
        if (spareCount.get() >= capacity) return
        spareCount.incrementAndGet()
        spare.offer(session)
    }

    /** Sessions idle in the pool now (for tests; not atomic across slots). */
    fun idle(): Int = (0 until slots.length() step STRIDE).count { slots.get(it) != null } + spareCount.get()

    /**
     * The first slot index of the calling thread: the top bits of its mixed id. (The id is a field
     * read; a thread's identity hash took about 25 ns once the thread's monitor had been inflated,
     * as `join` and `wait` do, against 2 ns before.)
     */
    private fun slotOfThisThread(): Int {
        if (slotShift == 32) return 0
        val hash = Thread.currentThread().id.toInt() * -0x61c88647
        return (hash ushr slotShift) * STRIDE
    }

    internal companion object {
        /** References between two slots: 16 of 4 bytes fill a 64-byte cache line, so no two slots share one. */
        private const val STRIDE = 16

        /** Four slots per processor, from 16 to 64: few threads of a core then share a slot. */
        fun slotsFor(processors: Int): Int = Integer.highestOneBit((4 * processors).coerceIn(16, 64))
    }
}

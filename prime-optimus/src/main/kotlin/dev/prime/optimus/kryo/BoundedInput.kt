package dev.prime.optimus.kryo

import com.esotericsoftware.kryo.io.Input

/**
 * A Kryo [Input] over one byte array that checks every length prefix before it allocates.
 *
 * Kryo's own bulk reads (`readBytes(n)`, `readInts(n)`, `readString()`, ...) allocate an array
 * of the length the bytes claim and only then notice the bytes run out; a crafted prefix of
 * 2^31 - 1 would cost gigabytes or an [OutOfMemoryError]. Every serializer, Kryo's or ours,
 * reads through these methods, so checking here covers them all.
 *
 * Not thread-safe: one instance belongs to one pooled session at a time.
 */
internal class BoundedInput : Input() {

    /** Forgets the last buffer, and a large char buffer left by a long string. */
    fun release() {
        setBuffer(EMPTY)
        if (chars.size > RETAINED_CHARS) chars = CharArray(INITIAL_CHARS)
    }

    override fun readBytes(length: Int): ByteArray {
        requireAvailable(length, 1, "a byte array")
        return super.readBytes(length)
    }

    override fun readChars(length: Int): CharArray {
        requireAvailable(length, Char.SIZE_BYTES, "a char array")
        return super.readChars(length)
    }

    override fun readShorts(length: Int): ShortArray {
        requireAvailable(length, Short.SIZE_BYTES, "a short array")
        return super.readShorts(length)
    }

    override fun readInts(length: Int): IntArray {
        requireAvailable(length, Int.SIZE_BYTES, "an int array")
        return super.readInts(length)
    }

    override fun readInts(length: Int, optimizePositive: Boolean): IntArray {
        requireAvailable(length, 1, "an int array") // variable-length: at least 1 byte each
        return super.readInts(length, optimizePositive)
    }

    override fun readLongs(length: Int): LongArray {
        requireAvailable(length, Long.SIZE_BYTES, "a long array")
        return super.readLongs(length)
    }

    override fun readLongs(length: Int, optimizePositive: Boolean): LongArray {
        requireAvailable(length, 1, "a long array") // variable-length: at least 1 byte each
        return super.readLongs(length, optimizePositive)
    }

    override fun readFloats(length: Int): FloatArray {
        requireAvailable(length, Float.SIZE_BYTES, "a float array")
        return super.readFloats(length)
    }

    override fun readDoubles(length: Int): DoubleArray {
        requireAvailable(length, Double.SIZE_BYTES, "a double array")
        return super.readDoubles(length)
    }

    override fun readBooleans(length: Int): BooleanArray {
        requireAvailable(length, 1, "a boolean array")
        return super.readBooleans(length)
    }

    override fun readString(): String? {
        checkStringLength()
        return super.readString()
    }

    override fun readStringBuilder(): StringBuilder? {
        checkStringLength()
        return super.readStringBuilder()
    }

    /**
     * Kryo writes short ASCII strings as bytes ending in a flagged byte (bounded by the input
     * itself), and every other string as a flagged varint "char count + 1" followed by UTF-8.
     * Peek at that count: each char takes at least one byte.
     */
    private fun checkStringLength() {
        if (!readVarIntFlag()) return // ASCII form: no length prefix to trust
        val start = position()
        val countPlusOne = readVarIntFlag(true)
        setPosition(start)
        if (countPlusOne > 1) requireAvailable(countPlusOne - 1, 1, "a string")
        else if (countPlusOne < 0) requireAvailable(countPlusOne, 1, "a string")
    }

    private companion object {
        private val EMPTY = ByteArray(0)
        private const val INITIAL_CHARS = 32
        private const val RETAINED_CHARS = 16 * 1024
    }
}

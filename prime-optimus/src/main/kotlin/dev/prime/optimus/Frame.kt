package dev.prime.optimus

import java.nio.ByteBuffer

/**
 * Many values in one Redis list entry. Redis spends its time per list entry far more than per
 * byte (a script copies every entry it pushes or moves), so what one step or one `publishAll`
 * produces travels as one entry instead of one entry per value.
 *
 * Layout, version 1 (all integers big-endian):
 * ```
 * 'F'  version(1)  sequence(8)  count(4)  { length(4) envelope(length) } x count
 * ```
 * Each element is a whole [Envelope] (magic `'P'`, kind, id, ...), so every value keeps its own
 * id inside a frame and consumers skip duplicates per value. `sequence` is always 0: a source
 * numbers its frames in a list of its own beside its log ([SourceKeys.numbers]), so publishing
 * stores the frame as it came, without the script building a renumbered copy of it.
 *
 * Batching is adaptive and adds no latency: a frame holds what is ready at that moment (one
 * step's outputs, one `publishAll`), nothing ever waits to fill one. A frame is acknowledged as a
 * whole and, after a crash, redelivered as a whole. A frame never exceeds the byte bound it is
 * packed to (values are split over several frames) unless it holds a single value.
 */
internal object Frame {
    const val MAGIC: Byte = 0x46 // 'F'
    const val VERSION: Byte = 1

    /** Magic, version, sequence, count. */
    const val HEADER: Int = 14

    /** The length prefix of each element. */
    const val PER_VALUE: Int = 4

    /** The most values a packed frame holds: one frame is at most one service step's worth ([StageService.BATCH]). */
    const val MAX_VALUES: Int = 256

    /** The most bytes a packed frame holds (unless a single value needs more): keeps the scripts' copies small. */
    const val DEFAULT_BYTES: Int = 1024 * 1024

    /** Whether [entry] is a frame (else it is a single envelope). */
    fun isFrame(entry: ByteArray): Boolean = entry.isNotEmpty() && entry[0] == MAGIC

    /**
     * Packs [envelopes], in order, into entries of at most [MAX_VALUES] values and [maxBytes] bytes
     * each (a frame with one value may be bigger). With [always] false, an entry of one value stays a plain envelope.
     */
    fun pack(envelopes: List<ByteArray>, maxBytes: Int, always: Boolean): List<ByteArray> {
        if (envelopes.isEmpty()) return emptyList()
        if (envelopes.size == 1 && !always) return envelopes
        val entries = ArrayList<ByteArray>(1)
        var from = 0
        while (from < envelopes.size) {
            var bytes = HEADER + PER_VALUE + envelopes[from].size
            var to = from + 1
            while (to < envelopes.size && to - from < MAX_VALUES && bytes + PER_VALUE + envelopes[to].size <= maxBytes) {
                bytes += PER_VALUE + envelopes[to].size
                to++
            }
            entries += if (to - from == 1 && !always) envelopes[from] else build(envelopes, from, to, bytes)
            from = to
        }
        return entries
    }

    private fun build(envelopes: List<ByteArray>, from: Int, to: Int, bytes: Int): ByteArray {
        val buffer = ByteBuffer.allocate(bytes)
        buffer.put(MAGIC).put(VERSION).putLong(0L).putInt(to - from)
        for (k in from until to) buffer.putInt(envelopes[k].size).put(envelopes[k])
        return buffer.array()
    }

    /**
     * Copies of the envelopes of [entry]: its elements if it is a frame, else the entry itself (the
     * services and readers read them in place, by [envelopeBounds]; this is for tools and tests).
     *
     * @throws CodecException if it is a frame of another version, or its lengths do not add up
     */
    fun envelopes(entry: ByteArray): List<ByteArray> {
        if (!isFrame(entry)) return listOf(entry)
        val bounds = envelopeBounds(entry)
        return List(bounds.size / 2) { k -> entry.copyOfRange(bounds[2 * k], bounds[2 * k] + bounds[2 * k + 1]) }
    }

    /**
     * Where the envelopes of [entry] lie, nothing copied: the offset and the length of each, in
     * pairs (`[0, entry.size]` for a plain envelope). The whole frame is checked before anything is
     * returned, so a frame with a bad tail gives no envelope at all.
     *
     * @throws CodecException if it is a frame of another version, or its lengths do not add up
     */
    fun envelopeBounds(entry: ByteArray): IntArray {
        if (!isFrame(entry)) return intArrayOf(0, entry.size)
        if (entry.size < HEADER) throw CodecException("truncated frame (${entry.size} bytes)")
        val buffer = ByteBuffer.wrap(entry)
        buffer.get()
        val version = buffer.get()
        if (version != VERSION) {
            throw CodecException(
                "a frame of version $version; this process reads version $VERSION (do all processes of the topology run " +
                    "the same Prime version?)",
            )
        }
        buffer.long // sequence
        val count = buffer.int
        // every element takes at least its length prefix: a count that cannot fit is refused before allocating
        if (count < 0 || count.toLong() * PER_VALUE > buffer.remaining()) throw CodecException("bad frame count $count")
        val bounds = IntArray(2 * count)
        for (k in 0 until count) {
            if (buffer.remaining() < PER_VALUE) throw CodecException("truncated frame: $k of $count values")
            val length = buffer.int
            if (length < 0 || length > buffer.remaining()) throw CodecException("bad frame element length $length")
            bounds[2 * k] = buffer.position()
            bounds[2 * k + 1] = length
            buffer.position(buffer.position() + length)
        }
        if (buffer.hasRemaining()) throw CodecException("${buffer.remaining()} bytes after the last value of a frame")
        return bounds
    }

    /** The number of values in [entry] (1 for a plain envelope); a bad frame counts as 1. */
    fun count(entry: ByteArray): Int =
        if (!isFrame(entry) || entry.size < HEADER) 1 else ByteBuffer.wrap(entry, 10, 4).int.coerceAtLeast(1)

    /**
     * What [entry] adds to a service's queue count: a frame's values, 1 for a single value, 0 for
     * a single request (a caller's request is not counted against the queue limit). The step
     * script counts the same way.
     */
    fun queued(entry: ByteArray): Int = when {
        isFrame(entry) -> if (entry.size < HEADER) 0 else ByteBuffer.wrap(entry, 10, 4).int
        Envelope.isValue(entry) -> 1
        else -> 0
    }

    /** The number of the first value and the count of one entry of a source's [SourceKeys.numbers] list. */
    fun numbered(number: ByteArray): Pair<Long, Int> = ByteBuffer.wrap(number).let { it.long to it.int }
}

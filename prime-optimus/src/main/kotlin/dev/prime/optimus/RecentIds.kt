package dev.prime.optimus

/**
 * The ids of the last [capacity] values a consumer handled, to recognise a value delivered twice
 * (a producer's retry after a lost reply). Memory is bounded: the oldest id is forgotten first.
 * Not thread-safe: one consumer owns it.
 *
 * Design note. Every value a service or reader handles is looked up and added, so this is on the
 * hot path of every flow. Ids mostly come in runs: a producer numbers its values with a counter
 * and a service keeps its input's id on its one output, so a frame's values carry consecutive
 * ids. The set therefore holds blocks of 64 ids: a slot of an open-addressing table (linear
 * probing, deletion by shifting the following slots back) holds a block number (`id shr 6`) and
 * a 64-bit mask of the block's ids it holds; a slot whose mask is 0 is empty. A run of ids lands
 * in a handful of slots, which stay in the CPU's cache from one value to the next; a scattered id
 * (a service's second output gets a mixed id) takes a slot of its own, as in a set of single ids.
 * The table grows with the blocks it holds and is kept at most a quarter full (a run of 4096 ids:
 * 65 blocks in 512 slots, 8 KiB; 4096 scattered ids: 16384 slots, 256 KiB). In
 * `RecentIdsBenchmark` a lookup and an add of the next id of a run cost 11–13 ns, against 33 ns
 * when the table held single ids (128 KiB whatever the ids, so mostly cache misses; a fifth of a
 * one-hop flow's JVM samples were in this class); scattered ids cost what they did (30–33 ns).
 * Half full, the table took half the room but scattered ids cost 42 ns.
 *
 * [ring] holds the ids in the order they came, to know which one to forget; it starts small and
 * doubles as ids come (its entries are in order until it first wraps, at [capacity]), so a
 * service or reader that handles few values holds under 1 KiB.
 */
internal class RecentIds(private val capacity: Int = DEFAULT_CAPACITY) {
    private var ring = LongArray(minOf(capacity, INITIAL))
    private var next = 0
    private var size = 0

    /** Slot `s` is `table[2s]` (block number) and `table[2s + 1]` (mask of its ids; 0: empty). */
    private var table = LongArray(2 * INITIAL_SLOTS)
    private var mask = INITIAL_SLOTS - 1
    private var blocks = 0

    /** Forgets every id, keeping the room the set grew to (so a set cleared for every batch stops allocating). */
    fun clear() {
        if (size == 0) return
        table.fill(0L)
        blocks = 0
        next = 0
        size = 0
    }

    /** How many ids the set has room for now, before it grows: 64 at first, at most [capacity]. */
    val room: Int get() = ring.size

    /** Slots of the table now (for tests: it grows with the blocks of 64 ids it holds, not with the ids). */
    internal val slots: Int get() = mask + 1

    operator fun contains(id: Long): Boolean {
        val block = id shr BLOCK_BITS
        var slot = slotOf(block)
        while (true) {
            val ids = table[2 * slot + 1]
            if (ids == 0L) return false
            if (table[2 * slot] == block) return ids and bitOf(id) != 0L
            slot = (slot + 1) and mask
        }
    }

    fun add(id: Long) {
        if (size == ring.size && size < capacity) ring = ring.copyOf(minOf(capacity, ring.size * 2)).also { next = size }
        if (!insert(id)) return
        if (size == capacity) remove(ring[next]) else size++
        ring[next] = id
        next = (next + 1) % ring.size
    }

    /** Adds [id] to the table; false if it was there. */
    private fun insert(id: Long): Boolean {
        val block = id shr BLOCK_BITS
        val bit = bitOf(id)
        var slot = slotOf(block)
        while (true) {
            val ids = table[2 * slot + 1]
            if (ids == 0L) break
            if (table[2 * slot] == block) {
                if (ids and bit != 0L) return false
                table[2 * slot + 1] = ids or bit
                return true
            }
            slot = (slot + 1) and mask
        }
        table[2 * slot] = block
        table[2 * slot + 1] = bit
        if (++blocks * 4 > slots) grow()
        return true
    }

    /** Doubles the table (the ids stay where the ring has them). */
    private fun grow() {
        val old = table
        table = LongArray(old.size * 2)
        mask = table.size / 2 - 1
        for (k in 0 until old.size / 2) {
            val ids = old[2 * k + 1]
            if (ids == 0L) continue
            var slot = slotOf(old[2 * k])
            while (table[2 * slot + 1] != 0L) slot = (slot + 1) and mask
            table[2 * slot] = old[2 * k]
            table[2 * slot + 1] = ids
        }
    }

    private fun remove(id: Long) {
        val block = id shr BLOCK_BITS
        var slot = slotOf(block)
        while (true) {
            if (table[2 * slot + 1] == 0L) return // not held
            if (table[2 * slot] == block) break
            slot = (slot + 1) and mask
        }
        val ids = table[2 * slot + 1] and bitOf(id).inv()
        table[2 * slot + 1] = ids
        if (ids != 0L) return
        blocks--
        // the block is empty: shift back the slots after it whose probe run passes through it
        var gap = slot
        var probe = (slot + 1) and mask
        while (true) {
            val held = table[2 * probe + 1]
            if (held == 0L) break
            val home = slotOf(table[2 * probe])
            // the slot may move to gap unless its home lies cyclically in (gap, probe]
            if (((probe - home) and mask) >= ((probe - gap) and mask)) {
                table[2 * gap] = table[2 * probe]
                table[2 * gap + 1] = held
                gap = probe
            }
            probe = (probe + 1) and mask
        }
        table[2 * gap] = 0L
        table[2 * gap + 1] = 0L
    }

    private fun slotOf(block: Long): Int {
        val mixed = block * -0x61c8864680b583ebL
        return (mixed xor (mixed ushr 32)).toInt() and mask
    }

    companion object {
        /** How many ids a set remembers unless told otherwise. */
        const val DEFAULT_CAPACITY = 4096

        /** The ids a new set has room for before its ring first grows. */
        private const val INITIAL = 64

        /** The slots of a new table: room for 4 blocks at most a quarter full. */
        private const val INITIAL_SLOTS = 16

        /** A block holds 64 ids: those that agree but for their low 6 bits. */
        private const val BLOCK_BITS = 6

        private fun bitOf(id: Long): Long = 1L shl (id and 63L).toInt()
    }
}

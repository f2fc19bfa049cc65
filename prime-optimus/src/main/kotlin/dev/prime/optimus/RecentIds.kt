package dev.prime.optimus

/**
 * The ids of the last [capacity] values a consumer handled, to recognise a value delivered twice
 * (a producer's retry after a lost reply). Memory is bounded: the oldest id is forgotten first.
 * Not thread-safe: one consumer owns it.
 *
 * Design note. Every value a service or reader handles is looked up and added, so the set holds
 * primitive longs (open addressing with linear probing in a table at most a quarter full,
 * deletion by shifting the following entries back) instead of boxing each id into a
 * `HashSet<Long>`. The table is that sparse for speed: at most half full, a miss probed 3.2 slots
 * on average, and a lookup and an add of an id in a full set of 4096 took 60.6 ns
 * (`RecentIdsBenchmark`; a `HashSet<Long>` 46.7 ns and 104 B); a quarter full, 1.5 slots and
 * 31.6–36.2 ns. Slot value 0 means empty; the id 0 itself is kept in a flag. The ring
 * and the table start small and double as ids come (the ring's entries are in order until it
 * first wraps, at [capacity]), so a service or reader that handles few values holds about 2.5
 * KiB, not the 160 KiB of a full set of 4096.
 */
internal class RecentIds(private val capacity: Int = 4096) {
    private var ring = LongArray(minOf(capacity, INITIAL))
    private var next = 0
    private var size = 0
    private var table = LongArray(tableSizeFor(ring.size))
    private var mask = table.size - 1
    private var hasZero = false

    /** Forgets every id, keeping the room the set grew to (so a set cleared for every batch stops allocating). */
    fun clear() {
        if (size == 0 && !hasZero) return
        table.fill(0L)
        next = 0
        size = 0
        hasZero = false
    }

    /** How many ids the set has room for now, before it grows: 64 at first, at most [capacity]. */
    val room: Int get() = ring.size

    operator fun contains(id: Long): Boolean {
        if (id == 0L) return hasZero
        var slot = slotOf(id)
        while (true) {
            val held = table[slot]
            if (held == 0L) return false
            if (held == id) return true
            slot = (slot + 1) and mask
        }
    }

    fun add(id: Long) {
        if (size == ring.size && size < capacity) grow()
        if (!insert(id)) return
        if (size == capacity) remove(ring[next]) else size++
        ring[next] = id
        next = (next + 1) % ring.size
    }

    /**
     * Doubles the ring (at most to [capacity]) and the table, before the ring first wraps: its
     * entries are in the order they came, so they keep it; the table is filled again from them.
     */
    private fun grow() {
        ring = ring.copyOf(minOf(capacity, ring.size * 2))
        next = size
        table = LongArray(tableSizeFor(ring.size))
        mask = table.size - 1
        for (i in 0 until size) {
            if (ring[i] != 0L) insert(ring[i])
        }
    }

    /** Adds [id] to the table; false if it was there. */
    private fun insert(id: Long): Boolean {
        if (id == 0L) return !hasZero.also { hasZero = true }
        var slot = slotOf(id)
        while (true) {
            val held = table[slot]
            if (held == id) return false
            if (held == 0L) {
                table[slot] = id
                return true
            }
            slot = (slot + 1) and mask
        }
    }

    private fun remove(id: Long) {
        if (id == 0L) {
            hasZero = false
            return
        }
        var slot = slotOf(id)
        while (table[slot] != id) {
            if (table[slot] == 0L) return
            slot = (slot + 1) and mask
        }
        // shift back the entries after it whose probe run passes through the freed slot
        var gap = slot
        var probe = (slot + 1) and mask
        while (true) {
            val held = table[probe]
            if (held == 0L) break
            val home = slotOf(held)
            // held may move to gap unless its home lies cyclically in (gap, probe]
            if (((probe - home) and mask) >= ((probe - gap) and mask)) {
                table[gap] = held
                gap = probe
            }
            probe = (probe + 1) and mask
        }
        table[gap] = 0L
    }

    private companion object {
        /** The ids a new set has room for before it first grows. */
        const val INITIAL = 64

        /** A table for [ids] ids: a power of two, at most a quarter full. */
        fun tableSizeFor(ids: Int): Int = Integer.highestOneBit(maxOf(2, ids) * 8 - 1)
    }

    private fun slotOf(id: Long): Int {
        val mixed = id * -0x61c8864680b583ebL
        return (mixed xor (mixed ushr 32)).toInt() and mask
    }
}

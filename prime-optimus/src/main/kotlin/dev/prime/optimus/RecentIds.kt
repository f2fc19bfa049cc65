package dev.prime.optimus

/**
 * The ids of the last [capacity] values a consumer handled, to recognise a value delivered twice
 * (a producer's retry after a lost reply). Memory is bounded: the oldest id is forgotten first.
 * Not thread-safe: one consumer owns it.
 */
internal class RecentIds(private val capacity: Int = 4096) {
    private val ring = LongArray(capacity)
    private var next = 0
    private var size = 0
    private val members = HashSet<Long>(capacity * 2)

    operator fun contains(id: Long): Boolean = id in members

    fun add(id: Long) {
        if (!members.add(id)) return
        if (size == capacity) members.remove(ring[next]) else size++
        ring[next] = id
        next = (next + 1) % capacity
    }
}

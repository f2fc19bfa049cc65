package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import kotlin.random.Random

/** [RecentIds] (a primitive open-addressing set) answers as a plain set of the last ids does. */
class RecentIdsTest {

    @Test
    fun remembersExactlyTheLastIdsAcrossEvictionsAndCollisions() {
        val random = Random(42)
        for (capacity in listOf(1, 3, 16, 64, 65, 100, 1000, 4096)) {
            val recent = RecentIds(capacity)
            val model = ArrayDeque<Long>()
            val members = HashSet<Long>()
            // few distinct ids (many repeats and probe collisions), the id 0 included, and ids far apart
            val pool = LongArray(capacity * 3 + 2) { if (it == 0) 0L else random.nextLong() } +
                LongArray(capacity + 1) { it.toLong() shl 40 }
            repeat(if (capacity > 64) 40_000 else 20_000) { step ->
                val id = pool[random.nextInt(pool.size)]
                assertEquals(id in members, id in recent, "capacity $capacity, step $step, id $id before adding")
                if (members.add(id)) {
                    model.addLast(id)
                    if (model.size > capacity) members.remove(model.removeFirst())
                }
                recent.add(id)
                if (step % 997 == 0) for (other in pool) assertEquals(other in members, other in recent, "capacity $capacity, step $step, id $other")
            }
        }
    }

    @Test
    fun startsSmallAndGrowsToItsCapacityAsIdsCome() {
        val recent = RecentIds(4096)
        assertEquals(64, recent.room, "a new set: room for 64 ids (2.5 KiB with its table), not 4096 (160 KiB)")
        repeat(64) { recent.add(it + 1L) }
        assertEquals(64, recent.room, "full, it has not grown yet")
        recent.add(65)
        assertEquals(128, recent.room, "the 65th id doubles it")
        repeat(100) { recent.add(7) } // an id it holds adds nothing
        assertEquals(128, recent.room)
        for (id in 66L..10_000L) recent.add(id)
        assertEquals(4096, recent.room, "it grows no further than its capacity")
        assertEquals((1L..10_000L).map { it > 10_000 - 4096 }, (1L..10_000L).map { it in recent }, "the last 4096 ids, across every doubling")
        assertEquals(3, RecentIds(3).room, "a capacity under 64 is the room from the start")
    }

    @Test
    fun aClearedSetForgetsEveryIdKeepsItsRoomAndGrowsAgainInOrder() {
        val recent = RecentIds(Int.MAX_VALUE)
        repeat(300) { recent.add(it.toLong()) } // the id 0 too
        assertEquals(512, recent.room)
        recent.clear()
        for (id in 0L until 300L) assertEquals(false, id in recent, "id $id after clear")
        assertEquals(512, recent.room, "a cleared set keeps the room it grew to")
        // refilled past its room: it grows from the ids added since the clear, and only those
        repeat(600) { recent.add(1000L + it) }
        assertEquals(1024, recent.room)
        for (id in 0L until 300L) assertEquals(false, id in recent, "old id $id after refilling")
        for (id in 1000L until 1600L) assertEquals(true, id in recent, "new id $id")
    }
}

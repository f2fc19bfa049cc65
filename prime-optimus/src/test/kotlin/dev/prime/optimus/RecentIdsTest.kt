package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import kotlin.random.Random

/** [RecentIds] (a primitive open-addressing set) answers as a plain set of the last ids does. */
class RecentIdsTest {

    @Test
    fun remembersExactlyTheLastIdsAcrossEvictionsAndCollisions() {
        val random = Random(42)
        for (capacity in listOf(1, 3, 16, 4096)) {
            val recent = RecentIds(capacity)
            val model = ArrayDeque<Long>()
            val members = HashSet<Long>()
            // few distinct ids (many repeats and probe collisions), the id 0 included, and ids far apart
            val pool = LongArray(capacity * 3 + 2) { if (it == 0) 0L else random.nextLong() } +
                LongArray(capacity + 1) { it.toLong() shl 40 }
            repeat(20_000) { step ->
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
}

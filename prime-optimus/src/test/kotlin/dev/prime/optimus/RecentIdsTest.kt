package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import kotlin.random.Random

/** [RecentIds] (a primitive open-addressing set of blocks of 64 ids) answers as a plain set of the last ids does. */
class RecentIdsTest {

    @Test
    fun remembersExactlyTheLastIdsAcrossEvictionsAndCollisions() {
        val random = Random(42)
        for (capacity in listOf(1, 3, 16, 64, 65, 100, 1000, 4096)) {
            // few distinct ids (many repeats and probe collisions), the id 0 included, and ids far apart
            val pool = LongArray(capacity * 3 + 2) { if (it == 0) 0L else random.nextLong() } +
                LongArray(capacity + 1) { it.toLong() shl 40 }
            followsTheModel(capacity, if (capacity > 64) 40_000 else 20_000, 997, { pool.asIterable() }) {
                pool[random.nextInt(pool.size)]
            }
        }
    }

    @Test
    fun remembersExactlyTheLastIdsOfRunsAcrossBlockEdges() {
        val random = Random(7)
        // runs of consecutive ids (as producers number them) that cross blocks of 64, negative ids, the ends of
        // the long range, and ids one block apart with the same low bits, mixed with scattered ones
        val starts = longArrayOf(-130, -1, 0, 62, 1000, Long.MIN_VALUE, Long.MAX_VALUE - 70, random.nextLong(), random.nextLong())
        for (capacity in listOf(1, 5, 64, 100, 4096)) {
            val seen = HashSet<Long>()
            followsTheModel(capacity, 30_000, 4999, { seen }) {
                when (random.nextInt(4)) {
                    0 -> random.nextLong()
                    1 -> starts[random.nextInt(starts.size)] + 64L * random.nextInt(3)
                    else -> starts[random.nextInt(starts.size)] + random.nextInt(140)
                }.also { seen += it }
            }
        }
    }

    /**
     * Adds [steps] ids from [next] to a set of [capacity] and to a model of it (the ids in order and
     * a hash set of the last [capacity]), checking each id before it is added, and every id of
     * [known] once every [checkEvery] steps.
     */
    private fun followsTheModel(capacity: Int, steps: Int, checkEvery: Int, known: () -> Iterable<Long>, next: () -> Long) {
        val recent = RecentIds(capacity)
        val model = ArrayDeque<Long>()
        val members = HashSet<Long>()
        repeat(steps) { step ->
            val id = next()
            assertEquals(id in members, id in recent, "capacity $capacity, step $step, id $id before adding")
            if (members.add(id)) {
                model.addLast(id)
                if (model.size > capacity) members.remove(model.removeFirst())
            }
            recent.add(id)
            if (step % checkEvery == 0) {
                for (other in known()) assertEquals(other in members, other in recent, "capacity $capacity, step $step, id $other")
            }
        }
    }

    @Test
    fun aRunOfIdsTakesAFewSlotsAndGivesThemBackAsItMovesOn() {
        val recent = RecentIds(4096)
        val start = Random(3).nextLong()
        for (k in 0L until 4096L) recent.add(start + k)
        assertEquals(512, recent.slots, "4096 consecutive ids: 65 blocks of 64, a quarter of 512 slots at most (8 KiB)")
        for (k in 4096L until 200_000L) recent.add(start + k)
        assertEquals(512, recent.slots, "blocks the window left are freed: the table does not grow")
        for (k in 200_000L - 4200L until 200_000L) {
            assertEquals(k >= 200_000L - 4096L, start + k in recent, "id ${start + k}: only the last 4096 are held")
        }
        val scattered = RecentIds(4096)
        repeat(4096) { scattered.add(Random(it).nextLong()) }
        assertEquals(16384, scattered.slots, "4096 scattered ids: a block each, a quarter of 16384 slots (256 KiB)")
    }

    @Test
    fun startsSmallAndGrowsToItsCapacityAsIdsCome() {
        val recent = RecentIds(4096)
        assertEquals(64, recent.room, "a new set: room for 64 ids (under 1 KiB with its table), not 4096")
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

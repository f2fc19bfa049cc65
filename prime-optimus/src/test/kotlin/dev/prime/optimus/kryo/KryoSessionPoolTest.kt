package dev.prime.optimus.kryo

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNotSame
import org.junit.jupiter.api.Assertions.assertSame
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.util.Collections
import java.util.IdentityHashMap
import java.util.concurrent.Callable
import java.util.concurrent.CountDownLatch
import java.util.concurrent.Executors
import java.util.concurrent.TimeUnit

/** The pool every encode and decode of a [dev.prime.optimus.KryoCodec] takes its Kryo session from. */
internal class KryoSessionPoolTest {

    private val registry = KryoRegistry(AllowList(emptyList(), emptySet(), false, javaClass.classLoader), 64)

    @Test
    fun `a session given back is the one the same thread gets next, and a second one taken meanwhile is another`() {
        val pool = KryoSessionPool(registry, capacity = 4)
        val first = pool.obtain()
        val second = pool.obtain()
        assertNotSame(first, second, "a session in use was handed out again")
        pool.free(first)
        assertSame(first, pool.obtain(), "the thread's own session was not reused")
        pool.free(second)
    }

    @Test
    fun `at most one session per slot and the capacity are kept idle`() {
        for (slots in listOf(1, 16)) {
            val pool = KryoSessionPool(registry, capacity = 3, slots = slots)
            val taken = List(20) { pool.obtain() }
            taken.forEach(pool::free)
            // one thread: its own slot keeps one, the shared queue the capacity, the rest are dropped
            assertEquals(1 + 3, pool.idle(), "idle sessions with $slots slot(s)")
        }
    }

    @Test
    fun `no session is in two threads' hands at once, with threads sharing a slot or not`() {
        for (slots in listOf(1, 2, 64)) {
            val pool = KryoSessionPool(registry, capacity = 2, slots = slots)
            val threads = 4
            val rounds = 20_000
            val held = Collections.synchronizedSet(Collections.newSetFromMap(IdentityHashMap<KryoSession, Boolean>()))
            val executor = Executors.newFixedThreadPool(threads)
            try {
                val start = CountDownLatch(1)
                val results = (0 until threads).map {
                    executor.submit(Callable {
                        check(start.await(10, TimeUnit.SECONDS)) { "not started" }
                        var twice = 0
                        repeat(rounds) {
                            val session = pool.obtain()
                            if (!held.add(session)) twice++
                            held.remove(session)
                            pool.free(session)
                        }
                        twice
                    })
                }
                start.countDown()
                val twice = results.sumOf { it.get(60, TimeUnit.SECONDS) }
                assertEquals(0, twice, "sessions handed to a thread while another held them, with $slots slot(s)")
                assertTrue(pool.idle() <= slots + 2 + threads, "idle sessions: ${pool.idle()}")
            } finally {
                executor.shutdownNow()
                assertTrue(executor.awaitTermination(10, TimeUnit.SECONDS))
            }
        }
    }

    @Test
    fun `a slot count that is not a power of two is refused`() {
        val e = assertThrows(IllegalArgumentException::class.java) { KryoSessionPool(registry, capacity = 1, slots = 12) }
        assertTrue(e.message!!.contains("power of two"), e.message)
    }
}

package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import java.util.concurrent.Callable
import java.util.concurrent.CountDownLatch
import java.util.concurrent.Executors
import java.util.concurrent.TimeUnit

internal class KryoCodecConcurrencyTest {

    @Test
    fun `many threads encode and decode different values at once and each gets its own back`() {
        val codec = KryoCodec.builder().register(Pose::class.java).register(Route::class.java).register(Packet::class.java).build()
        val threads = 8
        val rounds = 2_000
        val pool = Executors.newFixedThreadPool(threads)
        try {
            val start = CountDownLatch(1)
            val futures = (0 until threads).map { t ->
                pool.submit(Callable {
                    start.await(10, TimeUnit.SECONDS)
                    var checked = 0
                    for (i in 0 until rounds) {
                        val value: Any = when (i % 4) {
                            0 -> Route("t$t-$i", Pose(t.toDouble(), i.toDouble(), 0.0), List(i % 7) { Pose(it.toDouble(), t.toDouble(), i.toDouble()) }, mapOf("t" to t), null)
                            1 -> Packet(i, ByteArray(i % 300) { (it + t).toByte() })
                            2 -> "thread $t round $i " + "x".repeat(i % 50)
                            else -> mapOf(t to listOf(i, i + 1), "k$i" to Pose(1.0, 2.0, 3.0))
                        }
                        assertEquals(value, codec.decode(codec.encode(value)))
                        checked++
                    }
                    checked
                })
            }
            start.countDown()
            for (future in futures) assertEquals(rounds, future.get(60, TimeUnit.SECONDS))
        } finally {
            pool.shutdownNow()
            pool.awaitTermination(10, TimeUnit.SECONDS)
        }
    }
}

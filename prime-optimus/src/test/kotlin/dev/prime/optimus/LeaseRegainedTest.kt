package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.concurrent.CopyOnWriteArrayList
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * A host cut off in its block longer than its lease, whose lease another host held meanwhile and
 * released, with an entry of its own left in the processing list: when the first host comes back
 * and finds the lease free, it stores nothing of its stale batch, re-claims the lease as it reads
 * the list again, and handles what the other host left.
 */
class LeaseRegainedTest {

    @Test
    fun aHostThatFindsItsLeaseFreeAfterAnotherHeldItHandlesWhatTheOtherLeft() {
        val config = CoreConfig.builder().name("regained-${System.nanoTime()}").shutdownTimeout(Duration.ofSeconds(1)).build()
        val keys = Keys(config.name())
        val firstHeld = BlockGate()
        val secondIn = CountDownLatch(1)
        val secondGoesOn = CountDownLatch(1)
        val firstRan = CopyOnWriteArrayList<Int>()
        val secondRan = CopyOnWriteArrayList<Int>()
        fun host(url: String, block: (Int) -> Int): OptimusCore {
            val core = OptimusCore.builder().config(config).redis(url).leaseTime(Duration.ofSeconds(1))
                .hosting("work", Hosting.ORDERED).build()
            core.source("numbers", EventBlock<Int>()).then(core.chain("work") { x: Int -> block(x) })
            return core
        }
        EmbeddedRedis.start().use { redis ->
            FaultProxy(redis.uri).use { proxy ->
                Jedis(URI(redis.uri)).use { raw ->
                    host(proxy.url) { x ->
                        firstRan += x
                        if (x == 1) firstHeld.hold()
                        10 * x
                    }.use { first ->
                        first.start()
                        OptimusCore.builder().config(config).redis(redis.uri).hosts(emptyList()).build().use { client ->
                            val numbers = client.source("numbers", EventBlock<Int>())
                            val reader = numbers.then(client.chain("work") { x: Int -> x }).reader()
                            client.start()
                            client.publishAll(numbers, listOf(1))
                            assertTrue(firstHeld.awaitHeld(), "the first host took value 1")
                            proxy.freeze() // the first host is cut off in its block
                            val second = host(redis.uri) { x ->
                                secondRan += x
                                if (x == 2) {
                                    secondIn.countDown()
                                    awaitIgnoringInterrupts(secondGoesOn) // still in its block after its core closed
                                }
                                10 * x
                            }
                            try {
                                second.start() // a standby: it takes over once the first host's lease lapsed
                                assertEquals(10, reader.take(Duration.ofSeconds(20)).orElse(null), "the second host handled value 1")
                                client.publishAll(numbers, listOf(2))
                                assertTrue(secondIn.await(20, TimeUnit.SECONDS), "the second host took value 2")
                            } finally {
                                second.close() // value 2 stays in the processing list; the lease is released
                            }
                            assertEquals(1L, raw.llen(keys.serviceProcessing("work")), "value 2 waits in the processing list")
                            proxy.thaw()
                            firstHeld.open() // the first host's block returns with its stale batch (value 1)
                            val got = ArrayList<Int>()
                            got += reader.take(Duration.ofSeconds(20)).orElse(-1)
                            client.publishAll(numbers, listOf(3))
                            got += reader.take(Duration.ofSeconds(20)).orElse(-1)
                            secondGoesOn.countDown()
                            assertEquals(
                                listOf(20, 30),
                                got,
                                "value 2, which the second host left, was handled (the first host ran $firstRan, the second $secondRan)",
                            )
                            assertEquals(listOf(1, 2, 3), firstRan, "the first host handled value 1, then what the other left, then 3")
                            assertEquals(emptyList<Int>(), reader.drain(), "nothing stored twice")
                            assertEquals(0L, raw.llen(keys.serviceProcessing("work")), "nothing left in the processing list")
                        }
                    }
                }
            }
        }
    }

    private fun awaitIgnoringInterrupts(latch: CountDownLatch) {
        val deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(30)
        while (latch.count > 0 && System.nanoTime() < deadline) {
            try {
                latch.await(deadline - System.nanoTime(), TimeUnit.NANOSECONDS)
            } catch (_: InterruptedException) {
                // the core's close interrupts the block: it holds on, as a block that does not answer interrupts
            }
        }
    }
}

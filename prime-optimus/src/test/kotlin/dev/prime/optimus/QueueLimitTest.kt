package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.UUID
import java.util.concurrent.CopyOnWriteArrayList
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * A service's queue is bounded: a publish that finds no room within the publish timeout is
 * refused whole; a service feeding a full queue (an internal hop) waits and drops nothing.
 */
class QueueLimitTest {

    @Test
    fun aPublishToAFullQueueIsRefusedWithinTheTimeoutAndPublishesNothing() {
        OptimusCore.builder().redis(TestRedis.url).hosts(emptyList()).queueLimit("slow", 10)
            .publishTimeout(Duration.ofSeconds(1)).build().use { core ->
                val events = EventBlock<Int>()
                val numbers = core.source("numbers", events)
                numbers.then(core.chain("slow") { x: Int -> x })
                val reader = numbers.reader()
                core.start()
                core.publishAll(numbers, (0 until 10).toList())

                val started = System.nanoTime()
                val full = assertThrows(QueueFullException::class.java) { events.publish(10) }
                val waited = Duration.ofNanos(System.nanoTime() - started)
                assertTrue(waited >= Duration.ofMillis(900) && waited <= Duration.ofSeconds(2), "refused after $waited")
                assertEquals("slow", full.service)
                assertEquals(10, full.limit)
                assertTrue("queueLimit(\"slow\"" in full.message!!, full.message)

                assertThrows(QueueFullException::class.java) { core.publishAll(numbers, listOf(11, 12, 13)) }
                assertEquals((0 until 10).toList(), reader.drain(), "the refused publishes published nothing")
                Jedis(URI(TestRedis.url)).use { raw ->
                    // a frame holds many values: count values, not entries
                    assertEquals(10L, TestRedis.values(raw, core.keys.serviceInput("slow")))
                    assertEquals(10L, TestRedis.values(raw, core.keys.sourceLog("numbers")))
                }
            }
    }

    /**
     * architecture.md: on Optimus a service's queue outlives the process that hosts it, so a full
     * queue of a service whose host has stopped holds a publish of another process up until a
     * host takes values again (or the publish timeout passes).
     */
    @Test
    fun aFullQueueOfAStoppedHostHoldsAPublishUpUntilAHostTakesValuesAgain() {
        val topology = CoreConfig.builder().name("queue-outlives-${UUID.randomUUID().toString().take(8)}").build()
        val seen = CopyOnWriteArrayList<Int>()
        val taken = java.util.concurrent.Semaphore(0)
        fun declare(core: OptimusCore): dev.prime.Source<Int> = core.source("numbers", EventBlock<Int>()).also {
            it.then(core.chain("kept") { x: Int -> seen += x; taken.release(); x })
        }
        OptimusCore.builder().config(topology).redis(TestRedis.url).build().use { host ->
            declare(host)
            host.start() // registers the service's queue, then stops with its core
        }
        OptimusCore.builder().config(topology).redis(TestRedis.url).hosts(emptyList()).queueLimit("kept", 3)
            .publishTimeout(Duration.ofSeconds(1)).build().use { publisher ->
                val numbers = declare(publisher)
                publisher.start()
                publisher.publishAll(numbers, listOf(1, 2, 3))
                val full = assertThrows(QueueFullException::class.java) { publisher.publishAll(numbers, listOf(4)) }
                assertEquals("kept", full.service)
                assertEquals(emptyList<Int>(), seen, "no host ran the service meanwhile")
                OptimusCore.builder().config(topology).redis(TestRedis.url).build().use { again ->
                    declare(again)
                    again.start()
                    assertTrue(taken.tryAcquire(3, PATIENCE.seconds, TimeUnit.SECONDS), "the host that came back took what was queued")
                    assertEquals(listOf(1, 2, 3), seen.toList())
                    publisher.publishAll(numbers, listOf(4))
                    assertTrue(taken.tryAcquire(1, PATIENCE.seconds, TimeUnit.SECONDS), "and the value published then")
                }
            }
        assertEquals(listOf(1, 2, 3, 4), seen.toList())
    }

    @Test
    fun anInterruptedPublisherWaitingForRoomStopsAtOnceSaysSoAndPublishesNothing() {
        OptimusCore.builder().redis(TestRedis.url).hosts(emptyList()).queueLimit("stuck", 2)
            .publishTimeout(Duration.ofSeconds(30)).build().use { core ->
                val events = EventBlock<Int>()
                val numbers = core.source("numbers", events)
                numbers.then(core.chain("stuck") { x: Int -> x })
                core.start()
                core.publishAll(numbers, listOf(0, 1))
                Thread.currentThread().interrupt()
                val started = System.nanoTime()
                try {
                    // before: the interrupt looked like a closed core, and the event block dropped the value silently
                    val stopped = assertThrows(dev.prime.PrimeException::class.java) { events.publish(2) }
                    assertTrue(Thread.currentThread().isInterrupted, "the interrupt flag is kept")
                    assertTrue("interrupted" in stopped.message!!, stopped.message)
                    assertTrue(stopped !is QueueFullException && stopped !is dev.prime.CoreClosedException, stopped.toString())
                } finally {
                    Thread.interrupted()
                }
                assertTrue(Duration.ofNanos(System.nanoTime() - started) < Duration.ofSeconds(5), "a 30 s publish timeout was not waited out")
                Jedis(URI(TestRedis.url)).use { raw -> assertEquals(2L, TestRedis.values(raw, core.keys.serviceInput("stuck"))) }
            }
    }

    @Test
    fun thePublishTimeoutIsTheConfigsUnlessTheBuilderSetsOne() {
        fun refusedAfter(config: CoreConfig, builder: (OptimusCore.Builder) -> OptimusCore.Builder): Duration =
            builder(OptimusCore.builder().config(config).redis(TestRedis.url).hosts(emptyList()).queueLimit("full", 1)).build().use { core ->
                val events = EventBlock<Int>()
                core.source("numbers", events).then(core.chain("full") { x: Int -> x })
                core.start()
                events.publish(0)
                val started = System.nanoTime()
                assertThrows(QueueFullException::class.java) { events.publish(1) }
                Duration.ofNanos(System.nanoTime() - started)
            }
        val fromConfig = refusedAfter(CoreConfig.builder().publishTimeout(Duration.ofMillis(400)).build()) { it }
        assertTrue(fromConfig >= Duration.ofMillis(350) && fromConfig < Duration.ofSeconds(5), "the config's 400 ms: refused after $fromConfig")
        val fromBuilder = refusedAfter(CoreConfig.builder().publishTimeout(Duration.ofSeconds(30)).build()) {
            it.publishTimeout(Duration.ofMillis(400))
        }
        assertTrue(fromBuilder >= Duration.ofMillis(350) && fromBuilder < Duration.ofSeconds(5), "the builder's 400 ms: refused after $fromBuilder")
    }

    @Test
    fun aBatchLargerThanTheLimitIsRefusedAtOnce() {
        OptimusCore.builder().redis(TestRedis.url).hosts(emptyList()).queueLimit(5).build().use { core ->
            val numbers = core.source("numbers", EventBlock<Int>())
            numbers.then(core.chain("small") { x: Int -> x })
            core.start()
            val started = System.nanoTime()
            val full = assertThrows(QueueFullException::class.java) { core.publishAll(numbers, (0 until 6).toList()) }
            assertTrue(Duration.ofNanos(System.nanoTime() - started) < Duration.ofSeconds(5))
            assertTrue("6 values in one publish" in full.message!!, full.message)
        }
    }

    @Test
    fun aServiceFeedingAFullQueueWaitsAndDropsNothing() {
        val config = CoreConfig.builder().name("hop-" + UUID.randomUUID()).build()
        val seen = CopyOnWriteArrayList<Int>()
        val all = CountDownLatch(VALUES)
        OptimusCore.builder().config(config).redis(TestRedis.url).hosts("first").queueLimit("second", 5).build().use { front ->
            val numbers = declare(front) { }
            front.start()
            front.publishAll(numbers, (0 until VALUES).toList())
            Jedis(URI(TestRedis.url)).use { raw ->
                val second = front.keys.serviceInput("second")
                val deadline = System.nanoTime() + PATIENCE.toNanos()
                while (TestRedis.values(raw, second) < 5 && System.nanoTime() < deadline) Thread.sleep(10)
                val waiting = TestRedis.values(raw, second)
                assertTrue(waiting in 5L..(5L + StageService.BATCH), "the next service's queue holds $waiting")
                val upstream = TestRedis.values(raw, front.keys.serviceInput("first")) +
                    TestRedis.values(raw, front.keys.serviceProcessing("first"))
                assertEquals(VALUES.toLong(), waiting + upstream, "every value is in one of the queues")
            }
            OptimusCore.builder().config(config).redis(TestRedis.url).hosts("second").queueLimit("second", 5).build().use { back ->
                declare(back) { x ->
                    seen += x
                    all.countDown()
                }
                back.start()
                assertTrue(all.await(PATIENCE.seconds, TimeUnit.SECONDS), "${all.count} values did not arrive")
            }
        }
        assertEquals((0 until VALUES).map { it + 1 }, seen.toList())
    }

    private fun declare(core: OptimusCore, record: (Int) -> Unit): dev.prime.Source<Int> {
        val numbers = core.source("numbers", EventBlock<Int>())
        numbers.then(core.chain("first") { x: Int -> x + 1 }.then(core.chain("second") { x: Int -> record(x); x }))
        return numbers
    }

    private companion object {
        const val VALUES = 300
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

package dev.prime.optimus

import dev.prime.optimus.CompetingConsumersTest.Companion.takeAll
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration
import java.util.Optional
import kotlin.concurrent.thread

/**
 * [Hosting.ORDERED]: a second host is a standby (its start() succeeds), takes over when the active
 * host closes or is killed, keeps the order and duplicates nothing; and processes that disagree on
 * a service's hosting mode are refused with the fix.
 */
class OrderedHostingTest {

    @Test
    fun aStandbyTakesOverWhenTheActiveHostCloses() {
        val name = "ordered-close"
        val active = CompetingTopology.core(TestRedis.url, name, Hosting.ORDERED)
        CompetingTopology.declare(active, 1)
        CompetingTopology.core(TestRedis.url, name, Hosting.ORDERED).use { standby ->
            CompetingTopology.declare(standby, 1)
            CompetingTopology.core(TestRedis.url, name, null).use { publisher ->
                val (numbers, output) = CompetingTopology.declare(publisher, 0)
                val reader = output.reader()
                publisher.start()
                active.start()
                val started = System.nanoTime()
                standby.start()
                val took = Duration.ofNanos(System.nanoTime() - started)
                assertTrue(took < CompetingTopology.LEASE, "a standby's start() does not wait for the lease: $took")
                assertFalse(CompetingTopology.SERVICE in standby.serviceNames(), "the standby does not run it yet")
                (0 until 50).forEach(numbers::publish)
                assertEquals((0 until 50).toList(), takeAll(reader, 50))

                active.close()
                val closed = System.nanoTime()
                (50 until 100).forEach(numbers::publish)
                val next = takeAll(reader, 1)
                val takeover = Duration.ofNanos(System.nanoTime() - closed)
                println("OrderedHostingTest: the standby took over ${takeover.toMillis()} ms after the active host closed")
                assertTrue(takeover < Duration.ofSeconds(2), "within a third of the 1 s lease, bounded: $takeover")
                assertEquals((50 until 100).toList(), next + takeAll(reader, 49), "in order")
                assertEquals(Optional.empty<Int>(), reader.poll())
                assertTrue(CompetingTopology.SERVICE in standby.serviceNames(), "the former standby runs it")
            }
        }
    }

    @Test
    fun aOneHostServicesBlockingTakeWaitsInRedisAtMostAThirdOfTheLease() {
        // a take sent before the host froze must end before its lease can lapse: else it moves a value into the
        // service's one processing list after a successor took over, whose step acknowledges it unprocessed
        CompetingTopology.core(TestRedis.url, "ordered-take-wait", Hosting.ORDERED).use { core ->
            CompetingTopology.declare(core, 1)
            core.start()
            val wait = core.soleSeat(CompetingTopology.SERVICE).idleWaitSeconds
            assertTrue(
                wait > 0 && wait <= CompetingTopology.LEASE.toMillis() / 3 / 1000.0,
                "a blocking take waits $wait s with a ${CompetingTopology.LEASE.toMillis()} ms lease",
            )
        }
    }

    @Test
    fun aStandbyTakesOverFromAKilledHostInOrderWithNoLossOrDuplicate() {
        val name = "ordered-kill"
        val n = 400
        EmbeddedRedis.start().use { redis ->
            CompetingTopology.core(redis.uri, name, null).use { publisher ->
                val (numbers, output) = CompetingTopology.declare(publisher, 0)
                val reader = output.reader()
                publisher.start()
                val args = arrayOf(redis.uri, name, "ORDERED", "5")
                val lease = publisher.keys.hostLease(CompetingTopology.SERVICE)
                WorkerProcess.start(ConsumerWorkerMain::class.java, *args).use { active ->
                    val activeId = active.awaitLine("READY").substringAfter(' ')
                    WorkerProcess.start(ConsumerWorkerMain::class.java, *args).use { standby ->
                        val standbyId = standby.awaitLine("READY").substringAfter(' ') // its start() succeeded: it stands by
                        val publishing = thread(name = "ordered-kill-publisher") { (0 until n).forEach(numbers::publish) }
                        try {
                            val received = takeAll(reader, n / 4)
                            Jedis(URI(redis.uri)).use { jedis ->
                                assertEquals(activeId, jedis.get(lease)?.toString(UTF_8), "the first worker is the active host")
                                active.kill()
                                val killed = System.nanoTime()
                                val tookOver = CompetingConsumersTest.boundedWait(Duration.ofSeconds(10)) {
                                    jedis.get(lease)?.toString(UTF_8) == standbyId
                                }
                                val failover = Duration.ofNanos(System.nanoTime() - killed)
                                println("OrderedHostingTest: the standby JVM took over ${failover.toMillis()} ms after the kill (1 s lease)")
                                assertTrue(tookOver && failover <= Duration.ofMillis(2500), "within about the lease, bounded: $failover")
                            }
                            received += takeAll(reader, n - n / 4)
                            assertEquals((0 until n).toList(), received, "0 lost, 0 reordered")
                            assertEquals(Optional.empty<Int>(), reader.poll())
                            Jedis(URI(redis.uri)).use { jedis ->
                                assertEquals(n.toLong(), TestRedis.values(jedis, publisher.keys.sourceLog(output.name())), "0 duplicated")
                            }
                        } finally {
                            publishing.join(CompetingConsumersTest.PATIENCE.toMillis())
                        }
                    }
                }
            }
        }
    }

    /**
     * As above, with frames in flight: the values are published as frames of [FRAME] values, and
     * the active host is killed (SIGKILL) while its step holds several of them in its processing
     * list, its results not stored. The standby redoes those frames whole, in order; the reader
     * gets every value once.
     */
    @Test
    fun aStandbyRedoesTheFramesAKilledHostHeldInOrderWithNoLossOrDuplicate() {
        val name = "ordered-kill-frames"
        val frames = 8
        val n = frames * FRAME
        EmbeddedRedis.start().use { redis ->
            CompetingTopology.core(redis.uri, name, null).use { publisher ->
                val numbers = publisher.source("numbers", dev.prime.EventBlock<Int>())
                val output = numbers.then(publisher.chain(CompetingTopology.SERVICE) { x: Int -> x })
                val reader = output.reader()
                publisher.start()
                val args = arrayOf(redis.uri, name, "ORDERED", "5")
                val lease = publisher.keys.hostLease(CompetingTopology.SERVICE)
                val processing = publisher.keys.serviceProcessing(CompetingTopology.SERVICE)
                WorkerProcess.start(ConsumerWorkerMain::class.java, *args).use { active ->
                    val activeId = active.awaitLine("READY").substringAfter(' ')
                    WorkerProcess.start(ConsumerWorkerMain::class.java, *args).use { standby ->
                        val standbyId = standby.awaitLine("READY").substringAfter(' ')
                        for (f in 0 until frames) publisher.publishAll(numbers, (f * FRAME until (f + 1) * FRAME).toList())
                        // the first frame's results are out: the active host's next step holds the frames after it
                        val received = takeAll(reader, FRAME)
                        Jedis(URI(redis.uri)).use { jedis ->
                            assertEquals(activeId, jedis.get(lease)?.toString(UTF_8), "the first worker is the active host")
                            val held = jedis.lrange(processing, 0, -1)
                            active.kill()
                            println("OrderedHostingTest: killed the active host holding ${held.size} entries of ${held.sumOf(Frame::count)} values")
                            assertTrue(held.size > 1 && held.all { Frame.count(it) == FRAME }, "frames in flight: ${held.map(Frame::count)}")
                            val tookOver = CompetingConsumersTest.boundedWait(Duration.ofSeconds(10)) {
                                jedis.get(lease)?.toString(UTF_8) == standbyId
                            }
                            assertTrue(tookOver, "the standby took over")
                        }
                        received += takeAll(reader, n - FRAME)
                        assertEquals((0 until n).toList(), received, "0 lost, 0 reordered")
                        assertEquals(Optional.empty<Int>(), reader.take(Duration.ofMillis(500)), "0 duplicated at the reader")
                        Jedis(URI(redis.uri)).use { jedis ->
                            assertEquals(n.toLong(), TestRedis.values(jedis, publisher.keys.sourceLog(output.name())), "0 duplicated")
                            assertEquals(0L, jedis.llen(processing) + jedis.llen(publisher.keys.serviceInput(CompetingTopology.SERVICE)))
                        }
                    }
                }
            }
        }
    }

    @Test
    fun anActiveHostThatLosesItsLeaseStandsByAndTakesOverAgain() {
        val name = "ordered-lost"
        val reported = java.util.concurrent.CompletableFuture<Throwable>()
        val host = OptimusCore.builder()
            .config(dev.prime.CoreConfig.builder().name(name).errorHandler { _, _, error -> reported.complete(error) }.build())
            .redis(TestRedis.url).leaseTime(CompetingTopology.LEASE)
            .hosts(CompetingTopology.SERVICE).hosting(CompetingTopology.SERVICE, Hosting.ORDERED).build()
        host.use {
            CompetingTopology.declare(host, 0)
            CompetingTopology.core(TestRedis.url, name, null).use { publisher ->
                val (numbers, output) = CompetingTopology.declare(publisher, 0)
                val reader = output.reader()
                publisher.start()
                host.start()
                numbers.publish(1)
                assertEquals(listOf(1), takeAll(reader, 1))
                val lease = publisher.keys.hostLease(CompetingTopology.SERVICE)
                Jedis(URI(TestRedis.url)).use { jedis ->
                    // another instance holds the lease, as if this host had been frozen longer than it
                    jedis.set(lease, "intruder".toByteArray(UTF_8), redis.clients.jedis.params.SetParams().px(60_000))
                    val error = reported.get(CompetingConsumersTest.PATIENCE.seconds, java.util.concurrent.TimeUnit.SECONDS)
                    assertTrue(error.message!!.contains("stands by"), error.message)
                    assertFalse(CompetingTopology.SERVICE in host.serviceNames(), "it stopped the service")
                    jedis.del(lease) // the other host is gone: the former active one, standing by, takes over
                    numbers.publish(2)
                    assertEquals(listOf(2), takeAll(reader, 1))
                    assertEquals(host.instanceId, jedis.get(lease)?.toString(UTF_8))
                    assertTrue(CompetingTopology.SERVICE in host.serviceNames())
                }
            }
        }
    }

    @Test
    fun processesThatDisagreeOnAServicesHostingAreRefusedWithTheFix() {
        val name = "hosting-mismatch"
        CompetingTopology.core(TestRedis.url, name, Hosting.UNORDERED).use { first ->
            CompetingTopology.declare(first, 0)
            first.start()
            CompetingTopology.core(TestRedis.url, name, Hosting.ORDERED).use { ordered ->
                CompetingTopology.declare(ordered, 0)
                val e = assertThrows(IllegalStateException::class.java) { ordered.start() }
                assertTrue(
                    e.message!!.contains("service 'slow' is hosted UNORDERED by other processes, this one declares ORDERED") &&
                        e.message!!.contains("OptimusCore.Builder.hosting(service, Hosting.X)"),
                    e.message,
                )
            }
            val defaultCore = OptimusCore.builder().config(dev.prime.CoreConfig.builder().name(name).build())
                .redis(TestRedis.url).leaseTime(CompetingTopology.LEASE).hosts(CompetingTopology.SERVICE).build()
            defaultCore.use { exclusive ->
                CompetingTopology.declare(exclusive, 0)
                val started = System.nanoTime()
                val e = assertThrows(IllegalStateException::class.java) { exclusive.start() }
                assertTrue(e.message!!.contains("this one declares EXCLUSIVE"), e.message)
                assertTrue(Duration.ofNanos(System.nanoTime() - started) < CompetingTopology.LEASE, "refused at once")
                assertEquals(setOf<String>(), exclusive.serviceNames(), "the refused core runs nothing")
            }
        }
    }

    @Test
    fun aHostingModeForAServiceTheTopologyLacksIsRefused() {
        OptimusCore.builder().config(dev.prime.CoreConfig.builder().name("hosting-unknown").build())
            .redis(TestRedis.url).hosting("nope", Hosting.UNORDERED).build().use { core ->
                CompetingTopology.declare(core, 0)
                val e = assertThrows(IllegalArgumentException::class.java) { core.start() }
                assertTrue(e.message!!.contains("[nope]") && e.message!!.contains("does not declare"), e.message)
            }
    }

    private companion object {
        /** The values of one published frame. */
        const val FRAME = 50
    }
}

package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.Reader
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import redis.clients.jedis.params.SetParams
import java.net.URI
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration
import java.util.Optional
import java.util.concurrent.CompletableFuture
import java.util.concurrent.TimeUnit
import kotlin.concurrent.thread

/**
 * A service has one host at a time: a second process that would host it is refused at start(),
 * a killed host's successor takes over once its lease lapsed and loses nothing, and a host that
 * finds its lease taken stops the service and says so.
 */
class SingleHostTest {

    @Test
    fun aSecondHostOfAServiceIsRefusedAtStartAfterWaitingOneLease() {
        val config = CoreConfig.builder().name("single-host-refused").build()
        fun core() = OptimusCore.builder().config(config).redis(TestRedis.url).leaseTime(LEASE).hosts("double").build()
        core().use { first ->
            val events = EventBlock<Int>()
            val output = first.source("numbers", events).then(first.chain("double") { x: Int -> 2 * x }).reader()
            first.start()
            core().use { second ->
                second.source("numbers", EventBlock<Int>()).then(second.chain("double") { x: Int -> 2 * x })
                val started = System.nanoTime()
                val e = assertThrows(IllegalStateException::class.java) { second.start() }
                val waited = Duration.ofNanos(System.nanoTime() - started)
                assertTrue(e.message!!.contains("already hosted by") && e.message!!.contains("'double'"), e.message)
                assertTrue(e.message!!.contains("pid ${ProcessHandle.current().pid()}"), "names the holder's process: ${e.message}")
                assertTrue(waited >= LEASE && waited < LEASE + Duration.ofSeconds(5), "waited one lease time, bounded: $waited")
                assertEquals(setOf<String>(), second.serviceNames(), "the refused core runs nothing")
            }
            events.publish(21)
            assertEquals(42, output.take(PATIENCE).orElseThrow(), "the first host goes on")
        }
    }

    @Test
    fun aClosedHostReleasesItsLeaseSoTheNextStartsAtOnce() {
        val config = CoreConfig.builder().name("single-host-released").build()
        fun core() = OptimusCore.builder().config(config).redis(TestRedis.url).leaseTime(Duration.ofSeconds(30)).build()
        core().use { first ->
            first.chain("twice") { x: Int -> 2 * x }.toBlock()
            first.start()
        }
        core().use { second ->
            val twice = second.chain("twice") { x: Int -> 2 * x }.toBlock()
            val started = System.nanoTime()
            second.start()
            val took = Duration.ofNanos(System.nanoTime() - started)
            assertTrue(took < Duration.ofSeconds(10), "a released lease is claimed without waiting for its 30 s to lapse: $took")
            assertEquals(4, twice.process(2))
        }
    }

    @Test
    fun aHostThatFindsItsLeaseTakenStopsTheServiceAndReportsIt() {
        val name = "single-host-taken"
        val reported = CompletableFuture<Triple<String, Any, Throwable>>()
        val config = CoreConfig.builder().name(name)
            .errorHandler { service, input, error -> reported.complete(Triple(service, input, error)) }
            .build()
        val lease = Keys(name).hostLease("double")
        fun core() = OptimusCore.builder().config(config).redis(TestRedis.url).leaseTime(LEASE).hosts("double").build()
        Jedis(URI(TestRedis.url)).use { jedis ->
            core().use { host ->
                val events = EventBlock<Int>()
                val output = host.source("numbers", events).then(host.chain("double") { x: Int -> 2 * x }).reader()
                host.start()
                events.publish(1)
                assertEquals(2, output.take(PATIENCE).orElseThrow())

                // another instance holds the lease now, as if this process had been frozen longer than the lease
                jedis.set(lease, "intruder".toByteArray(UTF_8), SetParams().px(Duration.ofMinutes(1).toMillis()))
                val (service, _, error) = reported.get(PATIENCE.seconds, TimeUnit.SECONDS)
                assertEquals("double", service)
                assertTrue(error is IllegalStateException && error.message!!.contains("instance intruder"), error.toString())
                assertFalse("double" in host.serviceNames(), "the service is stopped")

                events.publish(5)
                assertEquals(Optional.empty<Int>(), output.take(Duration.ofSeconds(2)), "nobody processes it now")
                val input = Keys(name).serviceInput("double")
                assertEquals(1L, jedis.llen(input) + jedis.llen(Keys(name).serviceProcessing("double")), "the value waits in Redis")
                assertEquals("intruder", jedis.get(lease)?.toString(UTF_8), "the stopped host leaves the other's lease alone")

                jedis.del(lease) // the intruder is gone: a new host takes over and loses nothing
                core().use { successor ->
                    successor.source("numbers", EventBlock<Int>()).then(successor.chain("double") { x: Int -> 2 * x })
                    successor.start()
                    assertEquals(10, output.take(PATIENCE).orElseThrow())
                }
            }
        }
    }

    @Test
    fun aKilledHostsSuccessorTakesOverWithinTheLeaseAndLosesNothing() {
        val name = "single-host-failover"
        val n = 3000
        EmbeddedRedis.start().use { redis ->
            val config = CoreConfig.builder().name(name).sourceRetention(n).build()
            OptimusCore.builder().config(config).redis(redis.uri).leaseTime(LEASE).hosts(TwoProcessTopology.TEST_SERVICES).build().use { core ->
                val numbers = EventBlock<Int>()
                val output = TwoProcessTopology.declare(core, numbers).output.reader()
                core.start()
                val args = arrayOf(redis.uri, name, LEASE.toMillis().toString(), "host")
                LeaseWorkerMain.declaredHost(*args).use { first ->
                    LeaseWorkerMain.startHosting(first)
                    LeaseWorkerMain.declaredHost(*args).use { successor ->
                        val publisher = thread(name = "single-host-test-publisher") { (0 until n).forEach(numbers::publish) }
                        try {
                            val received = takeAll(output, n / 10)
                            val killed = System.nanoTime()
                            first.kill() // mid-stream
                            val ready = LeaseWorkerMain.startHosting(successor)
                            val takeover = Duration.ofNanos(System.nanoTime() - killed)
                            println("SingleHostTest: the successor took over ${takeover.toMillis()} ms after the kill ($ready ms in start())")
                            assertTrue(takeover <= LEASE + Duration.ofSeconds(1), "took over after $takeover; successor:\n${successor.output()}")
                            received += takeAll(output, n - n / 10)
                            assertEquals((0 until n).map { it * 2 + 1 }, received, "every value once, in order")
                            assertEquals(Optional.empty<Int>(), output.poll(), "no duplicates")
                        } finally {
                            publisher.join(PATIENCE.toMillis())
                        }
                    }
                }
            }
        }
    }

    private fun takeAll(reader: Reader<Int>, n: Int): MutableList<Int> = (0 until n).mapTo(ArrayList()) { i ->
        reader.take(PATIENCE).orElseThrow { AssertionError("value ${i + 1} of $n did not arrive within $PATIENCE") }
    }

    private companion object {
        val LEASE: Duration = Duration.ofSeconds(1)
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

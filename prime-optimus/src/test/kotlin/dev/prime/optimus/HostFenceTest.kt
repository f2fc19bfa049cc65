package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import redis.clients.jedis.params.SetParams
import java.net.URI
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration
import java.util.Optional
import java.util.concurrent.CompletableFuture
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * The step script fences a hosted service's step by its host lease: a step of a host whose lease
 * another instance took writes nothing (its input stays in the processing list for the new host),
 * and a step that finds the lease held by nobody waits for the heartbeat to re-claim it and then
 * stores its results once; an idle host checks its lease after each wait for input, so it takes
 * nothing more once another instance holds it. The lease is long here, so the heartbeat (every third of it) does not
 * see the change first: the step itself must.
 */
class HostFenceTest {

    @Test
    fun aStepWhoseLeaseAnotherInstanceTookWritesNothingAndStopsTheService() {
        val name = "host-fence-taken"
        val keys = Keys(name)
        val reported = CompletableFuture<Throwable>()
        val config = CoreConfig.builder().name(name).errorHandler { _, _, error -> reported.complete(error) }.build()
        val entered = CountDownLatch(1)
        val release = CountDownLatch(1)
        Jedis(URI(TestRedis.url)).use { jedis ->
            OptimusCore.builder().config(config).redis(TestRedis.url).leaseTime(LONG_LEASE).build().use { host ->
                val events = EventBlock<Int>()
                val output = host.source("numbers", events).then(
                    host.chain("double") { x: Int ->
                        entered.countDown()
                        check(release.await(PATIENCE.seconds, TimeUnit.SECONDS)) { "the test did not release the block" }
                        2 * x
                    },
                ).reader()
                host.start()
                events.publish(21)
                assertTrue(entered.await(PATIENCE.seconds, TimeUnit.SECONDS), "the service took the value")
                // another instance holds the lease now, as if this host had been frozen longer than the lease
                jedis.set(keys.hostLease("double"), "intruder".toByteArray(UTF_8), SetParams().px(Duration.ofMinutes(1).toMillis()))
                val released = System.nanoTime()
                release.countDown()

                val error = reported.get(PATIENCE.seconds, TimeUnit.SECONDS)
                val noticed = Duration.ofNanos(System.nanoTime() - released)
                assertTrue(error is IllegalStateException && error.message!!.contains("instance intruder"), error.toString())
                assertTrue(noticed < LONG_LEASE.dividedBy(3), "the step noticed, not the heartbeat: after $noticed")
                assertFalse("double" in host.serviceNames(), "the service is stopped")
                assertEquals(Optional.empty<Int>(), output.take(Duration.ofSeconds(1)), "no output was stored")
                assertEquals(
                    listOf(21),
                    jedis.lrange(keys.serviceProcessing("double"), 0, -1).flatMap(Frame::envelopes).map { decodeValue(host, it) },
                    "the value stays in the processing list for the new host",
                )
                assertEquals(0L, jedis.llen(keys.serviceInput("double")))
                assertEquals(0L, jedis.llen(keys.deadLetters("double")), "no dead letter either")
                assertEquals("intruder", jedis.get(keys.hostLease("double"))?.toString(UTF_8), "the other's lease is left alone")
            }
        }
    }

    @Test
    fun anIdleHostWhoseLeaseAnotherInstanceTookTakesNothingMore() {
        val name = "host-fence-idle"
        val keys = Keys(name)
        val reported = CompletableFuture<Throwable>()
        val config = CoreConfig.builder().name(name).errorHandler { _, _, error -> reported.complete(error) }.build()
        Jedis(URI(TestRedis.url)).use { jedis ->
            OptimusCore.builder().config(config).redis(TestRedis.url).leaseTime(IDLE_LEASE).build().use { host ->
                val events = EventBlock<Int>()
                val output = host.source("numbers", events).then(host.chain("double") { x: Int -> 2 * x }).reader()
                host.start()
                events.publish(1)
                assertEquals(2, output.take(PATIENCE).orElseThrow(), "the host works, then waits idle for input")
                val taken = System.nanoTime()
                jedis.set(keys.hostLease("double"), "intruder".toByteArray(UTF_8), SetParams().px(Duration.ofMinutes(1).toMillis()))

                val error = reported.get(PATIENCE.seconds, TimeUnit.SECONDS)
                val noticed = Duration.ofNanos(System.nanoTime() - taken)
                assertTrue(error is IllegalStateException && error.message!!.contains("instance intruder"), error.toString())
                // its wait for input lasts at most a second; the heartbeat comes every 20 s (it may come first by chance)
                assertTrue(noticed < IDLE_NOTICE, "the idle service noticed after its wait for input: after $noticed")
                events.publish(5)
                assertEquals(Optional.empty<Int>(), output.take(Duration.ofSeconds(2)), "nobody processes it")
                // in the input, or (if the heartbeat noticed while the service waited for input) in the processing list
                assertEquals(
                    1L,
                    jedis.llen(keys.serviceInput("double")) + jedis.llen(keys.serviceProcessing("double")),
                    "the value waits in Redis for the new host",
                )
            }
        }
    }

    @Test
    fun aStepThatFindsTheLeaseHeldByNobodyWaitsForTheHeartbeatAndStoresOnce() {
        val name = "host-fence-lapsed"
        val keys = Keys(name)
        val entered = CountDownLatch(1)
        val release = CountDownLatch(1)
        Jedis(URI(TestRedis.url)).use { jedis ->
            val config = CoreConfig.builder().name(name).build()
            OptimusCore.builder().config(config).redis(TestRedis.url).leaseTime(SHORT_LEASE).build().use { host ->
                val events = EventBlock<Int>()
                val output = host.source("numbers", events).then(
                    host.chain("double") { x: Int ->
                        if (x == 1) {
                            entered.countDown()
                            check(release.await(PATIENCE.seconds, TimeUnit.SECONDS)) { "the test did not release the block" }
                        }
                        2 * x
                    },
                ).reader()
                host.start()
                (1..5).forEach(events::publish)
                assertTrue(entered.await(PATIENCE.seconds, TimeUnit.SECONDS), "the service took the first value")
                // the lease lapsed (a pause just over the lease) or Redis lost it: nobody holds it
                assertEquals(1L, jedis.del(keys.hostLease("double")))
                release.countDown()
                val received = (1..5).map { i ->
                    output.take(PATIENCE).orElseThrow { AssertionError("value $i of 5 did not arrive within $PATIENCE") }
                }
                assertEquals(listOf(2, 4, 6, 8, 10), received, "every value once, in order")
                assertEquals(Optional.empty<Int>(), output.take(Duration.ofSeconds(1)), "no duplicates")
                assertTrue("double" in host.serviceNames(), "the service goes on")
                assertEquals(0L, jedis.llen(keys.serviceProcessing("double")), "everything acknowledged")
                assertTrue(jedis.get(keys.hostLease("double")) != null, "the heartbeat re-claimed the lease")
            }
        }
    }

    /** The value of a raw entry of a service list. */
    private fun decodeValue(core: OptimusCore, entry: ByteArray): Any? =
        Envelope.parse(entry).payload()?.let(core.codec::decode)

    private companion object {
        val LONG_LEASE: Duration = Duration.ofSeconds(30)
        val SHORT_LEASE: Duration = Duration.ofSeconds(3)
        val IDLE_LEASE: Duration = Duration.ofSeconds(60)
        val IDLE_NOTICE: Duration = Duration.ofSeconds(3)
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

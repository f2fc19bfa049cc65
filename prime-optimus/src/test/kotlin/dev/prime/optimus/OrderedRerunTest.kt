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
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicBoolean
import java.util.concurrent.atomic.AtomicInteger

/**
 * An ordered service that lost its host lease while its block ran stands by, and takes the
 * service over again only once that run has ended: never two runs of it at once in one process.
 * Before, the standby claimed the lease as soon as the other holder's lapsed and started a new
 * run beside the old one, which was still in its block: two runs of one service in one process,
 * sharing the service's state (its codec session, its recent ids) and the instance id the fence
 * checks, so the old run's next step would go through the fence.
 */
class OrderedRerunTest {

    @Test
    fun aServiceThatLostItsLeaseInItsBlockRunsAgainOnlyOnceThatBlockHasReturned() {
        val name = "ordered-rerun"
        val keys = Keys(name)
        val reported = CompletableFuture<Throwable>()
        val oldRun = BlockGate()
        val second = BlockGate()
        val running = AtomicInteger()
        val overlapped = AtomicBoolean()
        val config = CoreConfig.builder().name(name).errorHandler { _, _, error -> reported.complete(error) }.build()
        Jedis(URI(TestRedis.url)).use { jedis ->
            OptimusCore.builder().config(config).redis(TestRedis.url).leaseTime(LEASE)
                .hosting("double", Hosting.ORDERED).build().use { host ->
                    val events = EventBlock<Int>()
                    val output = host.source("numbers", events).then(
                        host.chain("double") { x: Int ->
                            if (running.incrementAndGet() > 1) overlapped.set(true)
                            try {
                                if (x == 1) oldRun.hold()
                                if (x == 2) second.hold()
                                2 * x
                            } finally {
                                running.decrementAndGet()
                            }
                        },
                    ).reader()
                    host.start()
                    events.publish(1)
                    assertTrue(oldRun.awaitHeld(), "the service took value 1")
                    // another instance holds the lease for a while, as if this host had been frozen longer than the lease
                    val lease = keys.hostLease("double")
                    jedis.set(lease, "intruder".toByteArray(UTF_8), SetParams().px(INTRUDER_LEASE.toMillis()))
                    val error = reported.get(PATIENCE.seconds, TimeUnit.SECONDS)
                    assertTrue(error.message!!.contains("stands by"), error.message)
                    events.publish(2)
                    events.publish(3)
                    // the intruder's lease lapses: a standby that did not wait for the run still in its block would
                    // claim the lease within a third of the lease time and start a run that takes value 2 and holds it
                    val newRunBesideTheOld = second.awaitHeld(INTRUDER_LEASE.plus(LEASE).plusSeconds(1))
                    oldRun.open()
                    assertTrue(second.awaitHeld(), "the service runs again and takes value 2")
                    second.open()

                    val received = (1..3).map { i ->
                        output.take(PATIENCE).orElseThrow { AssertionError("value $i of 3 did not arrive within $PATIENCE") }
                    }
                    assertEquals(listOf(2, 4, 6), received, "every value once, in order")
                    assertEquals(Optional.empty<Int>(), output.take(Duration.ofSeconds(1)), "no duplicates")
                    assertFalse(newRunBesideTheOld, "no new run while the stopped one was still in its block")
                    assertFalse(overlapped.get(), "never two runs of the block at once")
                    assertEquals(host.instanceId, jedis.get(lease)?.toString(UTF_8), "this host holds the lease again")
                    assertEquals(0L, jedis.llen(keys.serviceProcessing("double")), "everything acknowledged")
                }
        }
    }

    private companion object {
        val LEASE: Duration = Duration.ofSeconds(1)
        val INTRUDER_LEASE: Duration = Duration.ofMillis(1500)
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

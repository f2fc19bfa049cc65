package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.PrimeCore
import dev.prime.Reader
import dev.prime.Source
import dev.prime.liberty.LibertyCore
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNotNull
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.lang.management.ManagementFactory
import java.net.URI
import java.time.Duration
import java.util.concurrent.Callable
import java.util.concurrent.CountDownLatch
import java.util.concurrent.Executors
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicReference
import java.util.concurrent.locks.LockSupport

/**
 * A `start()` made while a declaration is under way on another thread sees that declaration: it
 * takes what the declaration left for it (a combinator's host lease), as a declaration that
 * began before the start leaves its hosting to `start()`.
 */
class StartDuringDeclarationTest {

    @Test
    fun aCombinatorDeclaredWhileStartBeginsHoldsItsHostLease() {
        val config = CoreConfig.builder().name("start-during-declaration-${System.nanoTime()}").build()
        LibertyCore().use { liberty ->
            val ticks = liberty.source("ticks", EventBlock<Int>())
            OptimusCore.builder().config(config).redis(TestRedis.url).build().use { core ->
                val inside = CountDownLatch(1)
                val release = CountDownLatch(1)
                // another core's source whose reader the merge's declaration opens, held there
                val held = object : Source<Int> {
                    override fun core(): PrimeCore = liberty

                    override fun name(): String = ticks.name()

                    override fun reader(): Reader<Int> {
                        inside.countDown()
                        release.await(PATIENCE.toMillis(), TimeUnit.MILLISECONDS)
                        return ticks.reader()
                    }
                }
                val threads = Executors.newFixedThreadPool(2)
                try {
                    val declaring = threads.submit(Callable { core.merge(held) })
                    assertTrue(inside.await(PATIENCE.toMillis(), TimeUnit.MILLISECONDS), "the merge's declaration is under way")
                    val startThread = AtomicReference<Thread>()
                    val starting = threads.submit { startThread.set(Thread.currentThread()); core.start() }
                    // until start() returned, or waits for the declaration under way
                    val until = System.nanoTime() + PATIENCE.toNanos()
                    var waitsForDeclaration = false
                    while (!starting.isDone && !waitsForDeclaration && System.nanoTime() < until) {
                        val thread = startThread.get()
                        val lock = thread?.let { ManagementFactory.getThreadMXBean().getThreadInfo(it.id)?.lockName }
                        waitsForDeclaration = lock != null && lock.startsWith("dev.prime.TopologyRecorder")
                        LockSupport.parkNanos(1_000_000)
                    }
                    assertTrue(starting.isDone || waitsForDeclaration, "start() neither returned nor waited within $PATIENCE")
                    release.countDown()
                    assertEquals("merge(ticks)", declaring.get(PATIENCE.toMillis(), TimeUnit.MILLISECONDS).name())
                    starting.get(PATIENCE.toMillis(), TimeUnit.MILLISECONDS)
                    assertTrue("merge(ticks)" in core.serviceNames(), "${core.serviceNames()}")
                    Jedis(URI(TestRedis.url)).use { jedis ->
                        assertNotNull(
                            jedis.get(core.keys.hostLease("merge(ticks)")),
                            "the merge runs here, so it holds its host lease (one process at a time runs it); leases: " +
                                jedis.keys(core.keys.hostLease("*").toString(Charsets.UTF_8)),
                        )
                    }
                } finally {
                    release.countDown()
                    threads.shutdownNow()
                    assertTrue(threads.awaitTermination(PATIENCE.toMillis(), TimeUnit.MILLISECONDS), "the threads ended")
                }
            }
        }
    }

    private companion object {
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.GenericService
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
import java.util.concurrent.CompletableFuture
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicBoolean
import java.util.concurrent.atomic.AtomicInteger

/**
 * A generic service has one host at a time, like every Optimus service: of two processes that
 * both would host it, the second is refused at start() and never runs it; a host that finds its
 * host lease taken stops the service (interrupting a waiting work step), shuts it down once and
 * reports it.
 */
class GenericServiceHostTest {

    /** Counts its steps; each work waits (interruptibly) for a moment, as a driver waits for its device. */
    private class Driver(works: Int) : GenericService {
        val initializations = AtomicInteger()
        val works = AtomicInteger()
        val shutdowns = AtomicInteger()
        val worked = CountDownLatch(works)
        val shutDown = CountDownLatch(1)
        val interrupted = AtomicBoolean()

        @Volatile
        var nextWorks = CountDownLatch(0)

        override fun initialize() {
            initializations.incrementAndGet()
        }

        override fun work() {
            works.incrementAndGet()
            worked.countDown()
            nextWorks.countDown()
            try {
                Thread.sleep(20)
            } catch (e: InterruptedException) {
                interrupted.set(true)
                throw e
            }
        }

        override fun shutdown() {
            shutdowns.incrementAndGet()
            shutDown.countDown()
        }
    }

    @Test
    fun aSecondProcessThatWouldHostTheSameGenericServiceIsRefusedAndNeverRunsIt() {
        val config = CoreConfig.builder().name("generic-single-host").build()
        fun core() = OptimusCore.builder().config(config).redis(TestRedis.url).leaseTime(LEASE).build()
        val first = Driver(3)
        val second = Driver(1)
        core().use { host ->
            host.service("driver", first)
            host.start()
            assertTrue(first.worked.await(PATIENCE.seconds, TimeUnit.SECONDS), "the first host runs it")
            core().use { other ->
                other.service("driver", second)
                val e = assertThrows(IllegalStateException::class.java) { other.start() }
                assertTrue(e.message!!.contains("already hosted by") && e.message!!.contains("'driver'"), e.message)
                assertFalse("driver" in other.serviceNames(), "the refused core runs nothing")
            }
            val more = CountDownLatch(2)
            first.nextWorks = more
            assertTrue(more.await(PATIENCE.seconds, TimeUnit.SECONDS), "the first host goes on")
            assertEquals(0, first.shutdowns.get())
            assertTrue("driver" in host.serviceNames())
        }
        assertEquals(0, second.initializations.get(), "the refused process never initialized it")
        assertEquals(0, second.works.get())
        assertEquals(0, second.shutdowns.get())
        assertEquals(1, first.initializations.get())
        assertEquals(1, first.shutdowns.get())
    }

    @Test
    fun aHostThatFindsItsLeaseTakenStopsTheGenericServiceShutsItDownAndReportsIt() {
        val name = "generic-lease-taken"
        val reported = CompletableFuture<Triple<String, Any, Throwable>>()
        val config = CoreConfig.builder().name(name)
            .errorHandler { service, input, error -> reported.complete(Triple(service, input, error)) }
            .build()
        val driver = Driver(2)
        Jedis(URI(TestRedis.url)).use { jedis ->
            OptimusCore.builder().config(config).redis(TestRedis.url).leaseTime(LEASE).build().use { host ->
                host.service("driver", driver)
                host.start()
                assertTrue(driver.worked.await(PATIENCE.seconds, TimeUnit.SECONDS), "it runs")

                // another instance holds the lease now, as if this process had been frozen longer than the lease
                val lease = Keys(name).hostLease("driver")
                jedis.set(lease, "intruder".toByteArray(UTF_8), SetParams().px(Duration.ofMinutes(1).toMillis()))
                val (service, _, error) = reported.get(PATIENCE.seconds, TimeUnit.SECONDS)
                assertEquals("driver", service)
                assertTrue(error is IllegalStateException && error.message!!.contains("instance intruder"), error.toString())
                assertTrue(driver.shutDown.await(PATIENCE.seconds, TimeUnit.SECONDS), "the lost service is shut down")
                assertTrue(driver.interrupted.get(), "its waiting work step was interrupted")
                assertFalse("driver" in host.serviceNames(), "the service is stopped")
                val works = driver.works.get()
                assertEquals(1, driver.shutdowns.get())
                assertEquals(works, driver.works.get(), "no work after its shutdown")
                assertEquals("intruder", jedis.get(lease)?.toString(UTF_8), "the stopped host leaves the other's lease alone")
                jedis.del(lease)
            }
        }
        assertEquals(1, driver.initializations.get())
        assertEquals(1, driver.shutdowns.get(), "close does not shut it down a second time")
    }

    private companion object {
        val LEASE: Duration = Duration.ofSeconds(1)
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

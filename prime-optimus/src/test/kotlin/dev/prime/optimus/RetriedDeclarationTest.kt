package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.GenericService
import dev.prime.Reader
import dev.prime.Source
import dev.prime.Tuple2
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicInteger

/**
 * A declaration after `start()` that hosts a service here and fails in the media (another process
 * holds a service's host lease, or its wait for Redis in an outage is interrupted) leaves the chain
 * unused and nothing of it bound: the same declaration, on the same chain, works once the cause is
 * gone, as a first declaration would.
 */
class RetriedDeclarationTest {

    private fun core(config: CoreConfig, redis: String = TestRedis.url): OptimusCore =
        OptimusCore.builder().config(config).redis(redis).leaseTime(LEASE).build()

    private fun config(name: String): CoreConfig = CoreConfig.builder().name("$name-${System.nanoTime()}").build()

    /** The instance that holds [service]'s host lease in topology [topology], or `null`. */
    private fun leaseHolder(topology: String, service: String): String? =
        Jedis(URI(TestRedis.url)).use { it.get(Keys(topology).hostLease(service))?.toString(Charsets.UTF_8) }

    @Test
    fun aToBlockRefusedByAHostLeaseHeldElsewhereCanBeMadeAgain() {
        val config = config("retried-to-block")
        core(config).use { second ->
            second.start()
            val ab = second.chain("a") { x: Int -> x + 1 }.then(second.chain("b") { x: Int -> x * 10 })
            core(config).use { holder ->
                holder.chain("b") { x: Int -> x * 10 }.toBlock()
                holder.start()
                val refused = assertThrows(IllegalStateException::class.java) { ab.toBlock() }
                assertDeclarationRefused(refused)
                assertTrue("already hosted by" in refused.message!! && "'b'" in refused.message!!, refused.message)
                assertNull(leaseHolder(config.name()!!, "a"), "the refused toBlock() holds no host lease of 'a'")
            }
            val block = ab.toBlock()
            assertEquals(20, block.process(1), "the same toBlock() works once the other host is gone")
        }
    }

    @Test
    fun aSourceLinkRefusedByAHostLeaseHeldElsewhereCanBeMadeAgain() {
        val config = config("retried-link")
        core(config).use { second ->
            val events = EventBlock<Int>()
            val numbers = second.source("numbers", events)
            second.start()
            val ab = second.chain("a") { x: Int -> x + 1 }.then(second.chain("b") { x: Int -> x * 10 })
            core(config).use { holder ->
                holder.chain("b") { x: Int -> x * 10 }.toBlock()
                holder.start()
                val refused = assertThrows(IllegalStateException::class.java) { second.link(numbers, ab) }
                assertDeclarationRefused(refused)
                assertTrue("already hosted by" in refused.message!! && "'b'" in refused.message!!, refused.message)
            }
            val results = second.link(numbers, ab).reader()
            events.publish(1)
            assertEquals(20, results.take(PATIENCE).orElseThrow(), "the same link works once the other host is gone")
        }
    }

    @Test
    fun aTemplateRefusedByAHostLeaseHeldElsewhereForOnePartCanBeMadeAgain() {
        val config = config("retried-template")
        core(config).use { second ->
            second.start()
            val a = second.chain("a") { x: Int -> x + 1 }
            val b = second.chain("b") { x: Int -> x * 10 }
            core(config).use { holder ->
                holder.chain("b") { x: Int -> x * 10 }.toBlock()
                holder.start()
                val refused = assertThrows(IllegalStateException::class.java) { second.ifThenElse({ x: Int -> x > 0 }, a, b) }
                assertDeclarationRefused(refused)
                assertTrue("already hosted by" in refused.message!! && "'b'" in refused.message!!, refused.message)
                assertNull(leaseHolder(config.name()!!, "a"), "the refused template holds no host lease of its part 'a'")
            }
            val chosen = second.ifThenElse({ x: Int -> x > 0 }, a, b).toBlock()
            assertEquals(2, chosen.process(1), "the same template works once the other host is gone")
            assertEquals(-10, chosen.process(-1), "both of its parts")
        }
    }

    @Test
    fun aTemplateRefusedForOnePartWhileItsOtherPartWaitsIdleForInputCanBeMadeAgain() {
        // a shutdown timeout shorter than an idle service's wait for input in Redis (a second with
        // this lease): the refused template's other part, which runs no block, is still taken back
        val config = CoreConfig.builder().name("retried-idle-part-${System.nanoTime()}")
            .shutdownTimeout(Duration.ofMillis(200)).build()
        val idleCore = { OptimusCore.builder().config(config).redis(TestRedis.url).leaseTime(Duration.ofSeconds(3)).build() }
        idleCore().use { second ->
            second.start()
            val a = second.chain("a") { x: Int -> x + 1 }
            val b = second.chain("b") { x: Int -> x * 10 }
            idleCore().use { holder ->
                holder.chain("b") { x: Int -> x * 10 }.toBlock()
                holder.start()
                val refused = assertThrows(IllegalStateException::class.java) { second.ifThenElse({ x: Int -> x > 0 }, a, b) }
                assertDeclarationRefused(refused)
            }
            val chosen = second.ifThenElse({ x: Int -> x > 0 }, a, b).toBlock()
            assertEquals(2, chosen.process(1), "the same template works once the other host is gone")
            assertEquals(-10, chosen.process(-1), "both of its parts")
        }
    }

    @Test
    fun aTemplateRefusedForOnePartLeavesItsPartOfAnotherCoreUnused() {
        val config = config("retried-foreign-part")
        val otherConfig = config("retried-foreign-part-other")
        core(otherConfig).use { other ->
            other.start()
            val x = other.chain("x") { v: Int -> v + 1 }
            core(config).use { second ->
                second.start()
                val b = second.chain("b") { v: Int -> v * 10 }
                core(config).use { holder ->
                    holder.chain("b") { v: Int -> v * 10 }.toBlock()
                    holder.start()
                    val refused = assertThrows(IllegalStateException::class.java) { second.ifThenElse({ v: Int -> v > 0 }, x, b) }
                    assertDeclarationRefused(refused)
                    assertNull(leaseHolder(otherConfig.name()!!, "x"), "the other core runs nothing for the refused template")
                }
                val chosen = second.ifThenElse({ v: Int -> v > 0 }, x, b).toBlock()
                assertEquals(2, chosen.process(1), "the same template, with the other core's chain, works once the other host is gone")
                assertEquals(-10, chosen.process(-1), "both of its parts")
            }
        }
    }

    @Test
    fun aCombinatorThatFailedAfterClaimingItsHostLeaseReleasesItAndCanBeMadeAgain() {
        val config = config("retried-combinator")
        core(config).use { core -> core(config("retried-combinator-other")).use { other ->
            val events = EventBlock<Int>()
            val numbers = core.source("numbers", events)
            val opened = AtomicInteger()
            val flaky = object : Source<Int> { // another core's source, whose first reader fails
                override fun core() = other
                override fun name() = "flaky"
                override fun reader(): Reader<Int> =
                    if (opened.incrementAndGet() == 1) throw IllegalStateException("this source cannot be read yet") else numbers.reader()
            }
            core.start()
            val refused = assertThrows(IllegalStateException::class.java) { core.combineLatest(numbers, flaky) }
            assertEquals("this source cannot be read yet", refused.message)
            assertNull(leaseHolder(config.name()!!, "combineLatest(numbers|flaky)"), "the failed combinator holds no host lease")
            val pairs = core.combineLatest(numbers, flaky).reader()
            events.publish(3)
            assertEquals(Tuple2(3, 3), pairs.take(PATIENCE).orElseThrow(), "the same combinator works when made again")
        } }
    }

    @Test
    fun aGenericServiceRefusedByAHostLeaseHeldElsewhereCanBeDeclaredAgain() {
        val config = config("retried-service")
        core(config).use { second ->
            second.start()
            core(config).use { holder ->
                holder.service("poller", GenericService { Thread.sleep(10) })
                holder.start()
                val refused = assertThrows(IllegalStateException::class.java) {
                    second.service("poller", GenericService { Thread.sleep(10) })
                }
                assertDeclarationRefused(refused)
                assertTrue("already hosted by" in refused.message!! && "'poller'" in refused.message!!, refused.message)
            }
            val worked = CountDownLatch(1)
            second.service("poller", GenericService { worked.countDown(); Thread.sleep(10) })
            assertTrue(worked.await(PATIENCE.toMillis(), TimeUnit.MILLISECONDS), "the service declared again runs")
            assertTrue("poller" in second.serviceNames(), "and runs here: ${second.serviceNames()}")
        }
    }

    @Test
    fun declarationsInterruptedInAnOutageCanBeMadeAgainOnceRedisIsBack() {
        val config = config("retried-interrupted")
        EmbeddedRedis.start().use { redis ->
            FaultProxy(redis.uri).use { proxy ->
                core(config, proxy.url).use { core ->
                    val events = EventBlock<Int>()
                    val numbers = core.source("numbers", events)
                    core.start()
                    proxy.refuse()
                    val late = core.chain("late") { x: Int -> x + 1 }
                    assertInterruptedInOutage("toBlock() after start()", "late") { late.toBlock() }
                    val linked = core.chain("linked") { x: Int -> x * 2 }
                    assertInterruptedInOutage("a link after start()", "numbers") { numbers.then(linked) }
                    assertInterruptedInOutage("a timer after start()", "tick") { core.timer("tick", Duration.ofMillis(20)) }
                    proxy.restore()
                    assertEquals(2, late.toBlock().process(1), "the same toBlock() works once Redis is back")
                    val doubled = numbers.then(linked).reader()
                    events.publish(4)
                    assertEquals(8, doubled.take(PATIENCE).orElseThrow(), "the same link works once Redis is back")
                    val ticks = core.timer("tick", Duration.ofMillis(20)).reader()
                    assertEquals(1L, ticks.take(PATIENCE).orElseThrow().count(), "the same timer ticks once Redis is back")
                }
            }
        }
    }

    @Test
    fun aGenericServiceInterruptedInAnOutageFailsSayingSoAndCanBeDeclaredAgain() {
        val config = config("retried-interrupted-service")
        EmbeddedRedis.start().use { redis ->
            FaultProxy(redis.uri).use { proxy ->
                core(config, proxy.url).use { core ->
                    core.start()
                    proxy.refuse()
                    assertInterruptedInOutage("a generic service after start()", "poller") {
                        core.service("poller", GenericService { Thread.sleep(10) })
                    }
                    assertTrue(core.isStarted && !core.isClosed, "the core is still open")
                    proxy.restore()
                    val worked = CountDownLatch(1)
                    core.service("poller", GenericService { worked.countDown(); Thread.sleep(10) })
                    assertTrue(worked.await(PATIENCE.toMillis(), TimeUnit.MILLISECONDS), "the service declared again runs")
                }
            }
        }
    }

    @Test
    fun theRefusalOfAServiceOrTimerDeclaredAfterStartSpeaksOfNoChain() {
        val config = config("retried-timer-or-service")
        core(config).use { second ->
            second.start()
            core(config).use { holder ->
                holder.service("poller", GenericService { Thread.sleep(10) })
                holder.timer("tick", Duration.ofMillis(50))
                holder.start()
                val service = assertThrows(IllegalStateException::class.java) {
                    second.service("poller", GenericService { Thread.sleep(10) })
                }
                val timer = assertThrows(IllegalStateException::class.java) { second.timer("tick", Duration.ofMillis(50)) }
                for (refused in listOf(service, timer)) {
                    assertDeclarationRefused(refused)
                    assertTrue("chain" !in refused.message!!, "a generic service or a timer is no chain: ${refused.message}")
                }
            }
        }
    }

    /** A refusal of a declaration after start() says so, not that the core cannot start. */
    private fun assertDeclarationRefused(refused: IllegalStateException) {
        assertTrue("declared after start()" in refused.message!! && "cannot start" !in refused.message!!, refused.message)
        assertTrue("can be made again" in refused.message!!, "says it can be made again: ${refused.message}")
    }

    private companion object {
        val LEASE: Duration = Duration.ofSeconds(1)
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.Reader
import dev.prime.Tick
import dev.prime.Tuple2
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration
import java.util.Optional
import java.util.concurrent.LinkedBlockingQueue
import java.util.concurrent.TimeUnit
import java.net.URI
import java.nio.charset.StandardCharsets.UTF_8
import redis.clients.jedis.Jedis
import redis.clients.jedis.params.SetParams
import org.junit.jupiter.api.Assertions.fail

/**
 * Combinators and timers run on the core's own threads, and on Optimus only in the process that
 * hosts them: two processes that declare the same topology emit each combined value and each tick
 * once, and a second process that would host them too is refused at start like for any service.
 */
class CombinatorHostingTest {

    private class Declared(val combined: Reader<Tuple2<Int, String>>, val ticks: Reader<Tick>, val a: EventBlock<Int>, val b: EventBlock<String>)

    private fun declare(core: OptimusCore): Declared {
        val a = EventBlock<Int>()
        val b = EventBlock<String>()
        val combined = core.combineLatest(core.source("a", a), core.source("b", b)).reader()
        val ticks = core.timer("tick", Duration.ofMillis(20)).reader()
        return Declared(combined, ticks, a, b)
    }

    @Test
    fun onlyTheHostingProcessCombinesAndTicks() {
        val config = CoreConfig.builder().name("combinator-hosting").build()
        fun core(vararg hosts: String) = OptimusCore.builder().config(config).redis(TestRedis.url).hosts(*hosts).build()
        core("combineLatest(a|b)", "tick").use { host ->
            core().use { other ->
                val there = declare(host)
                val here = declare(other)
                host.start()
                other.start()
                assertEquals(setOf("combineLatest(a|b)", "tick"), host.serviceNames())
                assertEquals(setOf<String>(), other.serviceNames())
                assertEquals(setOf("combineLatest(a|b)", "tick"), other.topology().hostedElsewhere().toSet())

                here.a.publish(1)
                here.b.publish("x")
                assertEquals(Tuple2(1, "x"), here.combined.take(PATIENCE).orElseThrow())
                assertEquals(Tuple2(1, "x"), there.combined.take(PATIENCE).orElseThrow())
                here.a.publish(2)
                assertEquals(Tuple2(2, "x"), here.combined.take(PATIENCE).orElseThrow())
                assertEquals(Optional.empty<Any>(), here.combined.take(QUIET), "each value is combined once, not once per process")

                val counts = (1..20).map { here.ticks.take(PATIENCE).orElseThrow().count() }
                assertEquals((1L..20L).toList(), counts, "one timer ticks: no tick twice, none missing")
            }
        }
    }

    @Test
    fun aSecondProcessThatWouldHostACombinatorIsRefusedAtStart() {
        val config = CoreConfig.builder().name("combinator-refused").build()
        fun core() = OptimusCore.builder().config(config).redis(TestRedis.url).leaseTime(LEASE).build()
        core().use { first ->
            val declared = declare(first)
            first.start()
            core().use { second ->
                declare(second)
                val e = assertThrows(IllegalStateException::class.java) { second.start() }
                assertTrue(e.message!!.contains("already hosted by") && e.message!!.contains("'combineLatest(a|b)'"), e.message)
            }
            declared.a.publish(1)
            declared.b.publish("y")
            assertEquals(Tuple2(1, "y"), declared.combined.take(PATIENCE).orElseThrow(), "the first host goes on")
        }
    }

    @Test
    fun aHostThatFindsTheLeaseOfACombinatorOrTimerTakenStopsEmittingAndReportsIt() {
        val name = "combinator-lease-taken"
        val reports = LinkedBlockingQueue<Pair<String, Throwable>>()
        val config = CoreConfig.builder().name(name)
            .errorHandler { service, _, error -> reports.add(service to error) }
            .build()
        OptimusCore.builder().config(config).redis(TestRedis.url).leaseTime(LEASE).build().use { host ->
            val declared = declare(host)
            host.start()
            declared.a.publish(1)
            declared.b.publish("x")
            assertEquals(Tuple2(1, "x"), declared.combined.take(PATIENCE).orElseThrow())
            declared.ticks.take(PATIENCE).orElseThrow()

            // another instance holds both leases now, as if this process had been frozen longer than the lease
            Jedis(URI(TestRedis.url)).use { jedis ->
                for (service in listOf("combineLatest(a|b)", "tick")) {
                    jedis.set(Keys(name).hostLease(service), "intruder".toByteArray(UTF_8), SetParams().px(Duration.ofMinutes(1).toMillis()))
                }
            }
            val stopped = (1..2).map { reports.poll(PATIENCE.seconds, TimeUnit.SECONDS) ?: fail("no report of a lost lease") }
            assertEquals(setOf("combineLatest(a|b)", "tick"), stopped.map { it.first }.toSet())
            assertTrue(stopped.all { it.second.message!!.contains("instance intruder") }, stopped.toString())
            assertEquals(setOf<String>(), host.serviceNames(), "neither runs here now")

            declared.ticks.drain() // ticks published before the lease was found taken
            declared.a.publish(2)
            assertEquals(Optional.empty<Any>(), declared.combined.take(Duration.ofSeconds(1)), "the combinator emits no more")
            // a tick already on its way when the lease was found taken may still land; a running timer would give ten
            val late = (1..10).mapNotNull { declared.ticks.take(Duration.ofMillis(300)).orElse(null) }
            assertTrue(late.size <= 1, "the timer ticks no more: $late")
        }
    }

    /**
     * A combinator or timer holds no batch, so the heartbeat claims its lapsed lease again (a
     * service with a processing list re-claims its own as it reads the list again): they go on.
     */
    @Test
    fun theLapsedLeaseOfACombinatorOrTimerIsClaimedAgainByTheHeartbeat() {
        val name = "combinator-lease-lapsed-${System.nanoTime()}"
        val config = CoreConfig.builder().name(name).build()
        OptimusCore.builder().config(config).redis(TestRedis.url).leaseTime(LEASE).build().use { host ->
            val declared = declare(host)
            host.start()
            declared.ticks.take(PATIENCE).orElseThrow()
            Jedis(URI(TestRedis.url)).use { jedis ->
                val leases = listOf("combineLatest(a|b)", "tick").map { Keys(name).hostLease(it) }
                assertEquals(2L, jedis.del(*leases.toTypedArray()), "both leases lapsed, as after a pause or a Redis that lost them")
                val pace = java.util.concurrent.CountDownLatch(1) // never counted down: a bounded pause between looks
                var looks = 0
                while (leases.any { jedis.get(it) == null } && looks++ < 200) pace.await(20, TimeUnit.MILLISECONDS)
                assertEquals(
                    listOf(host.instanceId, host.instanceId),
                    leases.map { jedis.get(it)?.toString(UTF_8) },
                    "the heartbeat claimed both leases again",
                )
            }
            assertEquals(setOf("combineLatest(a|b)", "tick"), host.serviceNames(), "both still run here")
            declared.a.publish(3)
            declared.b.publish("y")
            assertEquals(Tuple2(3, "y"), declared.combined.take(PATIENCE).orElseThrow(), "the combinator goes on")
        }
    }

    /**
     * A combinator or timer declared on a started core holds its host lease as one declared before
     * the start does: a second process that declares it too, after its own start, is refused
     * ("already hosted by") and emits nothing, so each value is combined and each tick published once.
     */
    @Test
    fun aCombinatorOrTimerDeclaredOnAStartedCoreHoldsItsHostLease() {
        val name = "combinator-after-start-${System.nanoTime()}"
        val config = CoreConfig.builder().name(name).build()
        fun core() = OptimusCore.builder().config(config).redis(TestRedis.url).leaseTime(LEASE).build()
        core().use { first ->
            first.start()
            val declared = declare(first)
            declared.ticks.take(PATIENCE).orElseThrow()
            Jedis(URI(TestRedis.url)).use { jedis ->
                assertEquals(
                    listOf(first.instanceId, first.instanceId),
                    listOf("combineLatest(a|b)", "tick").map { jedis.get(Keys(name).hostLease(it))?.toString(UTF_8) },
                    "the host leases of a combinator and a timer declared after start()",
                )
            }
            core().use { second ->
                second.start()
                val a = EventBlock<Int>()
                val b = EventBlock<String>()
                val e = assertThrows(IllegalStateException::class.java) {
                    second.combineLatest(second.source("a", a), second.source("b", b))
                }
                assertTrue(e.message!!.contains("already hosted by") && e.message!!.contains("'combineLatest(a|b)'"), e.message)
                val t = assertThrows(IllegalStateException::class.java) { second.timer("tick", Duration.ofMillis(20)) }
                assertTrue(t.message!!.contains("already hosted by") && t.message!!.contains("'tick'"), t.message)
            }
            declared.ticks.drain()
            val counts = (1..5).map { declared.ticks.take(PATIENCE).orElseThrow().count() }
            assertEquals((counts[0]..counts[0] + 4).toList(), counts, "the first host's timer goes on, each tick once")
        }
    }

    private companion object {
        val PATIENCE: Duration = Duration.ofSeconds(20)
        val QUIET: Duration = Duration.ofMillis(500)
        val LEASE: Duration = Duration.ofSeconds(1)
    }
}

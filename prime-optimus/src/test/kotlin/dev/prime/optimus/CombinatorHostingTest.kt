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

    private companion object {
        val PATIENCE: Duration = Duration.ofSeconds(20)
        val QUIET: Duration = Duration.ofMillis(500)
        val LEASE: Duration = Duration.ofSeconds(1)
    }
}

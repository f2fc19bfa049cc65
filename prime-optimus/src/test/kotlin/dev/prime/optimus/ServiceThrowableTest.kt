package dev.prime.optimus

import dev.prime.ChainFailedException
import dev.prime.CoreConfig
import dev.prime.ErrorHandler
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertSame
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Test
import java.time.Duration
import java.util.concurrent.CopyOnWriteArrayList

/** An `Error` thrown by a block (here an `AssertionError`) does not kill a service, on any path. */
class ServiceThrowableTest {

    private class Reported(val service: String, val input: Any, val error: Throwable)

    @Test
    fun anAssertionErrorReachesTheErrorHandlerAndTheServiceGoesOn() {
        val reported = CopyOnWriteArrayList<Reported>()
        val handler = ErrorHandler { service, input, error -> reported += Reported(service, input, error) }
        val boom = AssertionError("boom")
        OptimusCore.builder().config(CoreConfig.builder().errorHandler(handler).build()).redis(TestRedis.url)
            .callTimeout(Duration.ofSeconds(20)).build().use { core ->
                val events = EventBlock<Int>()
                val numbers = core.source("numbers", events)
                val out = numbers.then(core.chain("fragile") { x: Int -> if (x == 1) throw boom else x * 10 }).reader()
                val filtered = numbers.filter { x -> if (x == 2) throw boom else true }.reader()
                val call = core.chain("fragileCall") { x: Int -> if (x == 1) throw boom else x + 1 }.toBlock()
                core.start()

                events.publish(1)
                events.publish(2)
                events.publish(3)
                assertEquals(20, out.take(PATIENCE).orElseThrow())
                assertEquals(30, out.take(PATIENCE).orElseThrow())
                assertEquals(1, filtered.take(PATIENCE).orElseThrow())
                assertEquals(3, filtered.take(PATIENCE).orElseThrow())

                val failed = assertThrows(ChainFailedException::class.java) { call.process(1) }
                assertSame(boom, failed.cause, "a synchronous caller gets the block's own throwable")
                assertEquals(3, call.process(2), "the called service still runs")

                val byService = reported.associateBy { it.service }
                assertEquals(setOf("fragile", "filter(numbers)"), byService.keys)
                assertEquals(1, byService.getValue("fragile").input)
                assertSame(boom, byService.getValue("fragile").error)
                assertEquals(2, byService.getValue("filter(numbers)").input)
                assertSame(boom, byService.getValue("filter(numbers)").error)
            }
    }

    private companion object {
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.PrimeException
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/**
 * A `start()` that waits for an unreachable Redis and meets its thread's interrupt flag ends with
 * a [PrimeException] that says so and what to do, the flag kept: never as [CoreClosedException],
 * since the core is open (and still closes).
 */
class InterruptedStartTest {

    @Test
    fun aStartInterruptedWhileRedisIsUnreachableFailsSayingSoAndKeepsTheFlag() {
        val config = CoreConfig.builder().name("interrupted-start-${System.nanoTime()}").build()
        EmbeddedRedis.start().use { redis ->
            FaultProxy(redis.uri).use { proxy ->
                val core = OptimusCore.builder().config(config).redis(proxy.url).build()
                core.use {
                    core.chain("double") { x: Int -> x * 2 }.toBlock()
                    proxy.refuse()
                    val failure = assertInterruptedInOutage("start()", core.name()) { core.start() }
                    assertFalse(core.isClosed)
                    assertTrue(failure.message!!.contains("new one"), "says what to do: ${failure.message}")
                    proxy.restore()
                }
                assertTrue(core.isClosed, "the core closes")
            }
        }
    }

    /** The same for a start() that waits for the host lease of a live process to lapse. */
    @Test
    fun aStartInterruptedWhileAnotherProcessHoldsItsServiceFailsSayingSoAndKeepsTheFlag() {
        val config = CoreConfig.builder().name("interrupted-start-lease-${System.nanoTime()}").build()
        OptimusCore.builder().config(config).redis(TestRedis.url).hosts("double").build().use { holder ->
            holder.chain("double") { x: Int -> x * 2 }.toBlock()
            holder.start()
            val core = OptimusCore.builder().config(config).redis(TestRedis.url).hosts("double").build()
            core.use {
                core.chain("double") { x: Int -> x * 2 }.toBlock()
                val failure = assertInterruptedInOutage("start()", core.name()) { core.start() }
                assertTrue(failure.message!!.contains("host lease"), "says what it waited for: ${failure.message}")
                assertFalse(core.isClosed)
            }
            assertTrue(core.isClosed, "the core closes")
        }
    }
}

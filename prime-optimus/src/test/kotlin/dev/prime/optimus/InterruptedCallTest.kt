package dev.prime.optimus

import dev.prime.Block
import dev.prime.CoreConfig
import dev.prime.PrimeException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.util.concurrent.Callable
import java.util.concurrent.ExecutionException
import java.util.concurrent.Executors
import java.util.concurrent.TimeUnit

/**
 * A call whose wait to reach Redis (an outage) meets its thread's interrupt flag ends with a
 * [PrimeException] that says it was interrupted, the flag kept, as an interrupted wait for the
 * reply does: never as [CoreClosedException], since the core is open.
 */
class InterruptedCallTest {

    /** The calling thread's first call, which records its reply list first. */
    @Test
    fun aFirstCallInterruptedWhileRedisIsUnreachableFailsSayingSoAndKeepsTheFlag() {
        withCallerThroughProxy("interrupted-first-call") { proxy, double ->
            val failure = assertInterruptedCall(proxy, double)
            // interrupted while it recorded its reply list, before it sent anything
            assertTrue("its request was not sent" in failure.message!!, "says nothing was sent: ${failure.message}")
        }
    }

    /** A later call (its reply list recorded before the outage): whichever wait meets the flag, the same failure. */
    @Test
    fun aLaterCallInterruptedWhileRedisIsUnreachableFailsSayingSoAndKeepsTheFlag() {
        withCallerThroughProxy("interrupted-call") { proxy, double ->
            assertEquals(4, double.process(2), "a call before the outage")
            assertInterruptedCall(proxy, double)
        }
    }

    private fun assertInterruptedCall(proxy: FaultProxy, double: Block<Int, Int>): PrimeException {
        proxy.refuse()
        val failure = assertInterruptedInOutage("a call", "double") { double.process(1) }
        proxy.restore()
        assertEquals(6, double.process(3), "the chain is called on")
        return failure
    }

    /**
     * Runs [test] on a thread of its own (each test's first call is that thread's first), with the
     * block of chain `double` of a core that reaches Redis through a [FaultProxy]; the chain is
     * hosted by another core that reaches Redis directly.
     */
    private fun withCallerThroughProxy(name: String, test: (FaultProxy, Block<Int, Int>) -> Unit) {
        val config = CoreConfig.builder().name("$name-${System.nanoTime()}").build()
        EmbeddedRedis.start().use { redis ->
            FaultProxy(redis.uri).use { proxy ->
                OptimusCore.builder().config(config).redis(redis.uri).hosts("double").build().use { host ->
                    host.chain("double") { x: Int -> x * 2 }.toBlock()
                    host.start()
                    OptimusCore.builder().config(config).redis(proxy.url).hosts(emptyList()).build().use { caller ->
                        val double = caller.chain("double") { x: Int -> x * 2 }.toBlock()
                        caller.start()
                        val thread = Executors.newSingleThreadExecutor()
                        try {
                            try {
                                thread.submit(Callable { test(proxy, double) }).get(60, TimeUnit.SECONDS)
                            } catch (e: ExecutionException) {
                                throw e.cause!!
                            }
                        } finally {
                            thread.shutdownNow()
                        }
                    }
                }
            }
        }
    }
}

package dev.prime.optimus

import dev.prime.CoreClosedException
import dev.prime.CoreConfig
import dev.prime.PrimeException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.function.Executable

/**
 * Reading or clearing a service's dead letters while Redis is unreachable waits for Redis; an
 * interrupt of the waiting thread ends that wait with a [PrimeException] that says so, the flag
 * kept, as a call's or a publish's does: never as [CoreClosedException], since the core is open.
 */
class InterruptedDeadLettersTest {

    @Test
    fun readingDeadLettersInterruptedWhileRedisIsUnreachableFailsSayingSoAndKeepsTheFlag() {
        val config = CoreConfig.builder().name("interrupted-dead-letters-${System.nanoTime()}").build()
        EmbeddedRedis.start().use { redis ->
            FaultProxy(redis.uri).use { proxy ->
                OptimusCore.builder().config(config).redis(proxy.url).hosts(emptyList()).build().use { core ->
                    core.start()
                    assertEquals(listOf<DeadLetter>(), core.deadLetters("double"), "read before the outage")
                    proxy.refuse()
                    assertInterrupted("reading the dead letters", core) { core.deadLetters("double") }
                    assertInterrupted("reading how many dead letters", core) { core.trimmedDeadLetters("double") }
                    assertInterrupted("clearing the dead letters", core) { core.clearDeadLetters("double") }
                    proxy.restore()
                    assertEquals(0L, core.trimmedDeadLetters("double"), "read again once Redis is back")
                    assertEquals(0, core.clearDeadLetters("double"), "cleared once Redis is back")
                }
            }
        }
    }

    /** [action] on a thread whose interrupt flag is set, while Redis is unreachable: says so, keeps the flag. */
    private fun assertInterrupted(what: String, core: OptimusCore, action: () -> Unit) {
        Thread.currentThread().interrupt()
        val failure = try {
            assertThrows(PrimeException::class.java, Executable { action() }, what)
        } finally {
            assertTrue(Thread.interrupted(), "$what: the flag is kept (and cleared here)")
        }
        assertFalse(failure is CoreClosedException, "$what: the core is open: $failure")
        assertFalse(core.isClosed, what)
        assertTrue(failure.message!!.contains("interrupted"), "$what: says why: ${failure.message}")
        assertTrue(failure.message!!.contains("'double'"), "$what: names the service: ${failure.message}")
    }
}

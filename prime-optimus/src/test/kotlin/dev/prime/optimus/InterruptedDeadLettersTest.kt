package dev.prime.optimus

import dev.prime.CoreConfig
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Test

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
                    assertInterruptedInOutage("reading the dead letters", "double") { core.deadLetters("double") }
                    assertInterruptedInOutage("reading how many dead letters", "double") { core.trimmedDeadLetters("double") }
                    assertInterruptedInOutage("clearing the dead letters", "double") { core.clearDeadLetters("double") }
                    assertFalse(core.isClosed, "the core is open")
                    proxy.restore()
                    assertEquals(0L, core.trimmedDeadLetters("double"), "read again once Redis is back")
                    assertEquals(0, core.clearDeadLetters("double"), "cleared once Redis is back")
                }
            }
        }
    }
}

package dev.prime.optimus

import dev.prime.CoreClosedException
import dev.prime.CoreConfig
import dev.prime.PrimeException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.assertThrows

/**
 * A declaration after `start()` begun on a thread whose interrupt flag is already set ends before
 * it asks Redis anything (as a blocking Java method refuses to start with the flag set): its
 * [PrimeException] says the flag was already set, not that it was interrupted while it waited,
 * for it never waited; the flag is kept, and the same declaration works once it is cleared.
 */
class FlagSetDeclarationTest {

    @Test
    fun aDeclarationBegunWithTheFlagSetSaysSoNotThatItWaited() {
        val config = CoreConfig.builder().name("flag-set-declaration-${System.nanoTime()}").build()
        EmbeddedRedis.start().use { redis ->
            OptimusCore.builder().config(config).redis(redis.uri).build().use { core ->
                core.start()
                val late = core.chain("late") { x: Int -> x + 1 }
                Thread.currentThread().interrupt()
                val failure = try {
                    assertThrows<PrimeException> { late.toBlock() }
                } finally {
                    assertTrue(Thread.interrupted(), "the flag is kept")
                }
                assertFalse(failure is CoreClosedException, "the core is open: $failure")
                val message = failure.message.orEmpty()
                assertTrue(message.contains("interrupt flag was already set as it began"), "it says the flag was already set: $message")
                assertFalse(message.contains("while it waited"), "it never waited: $message")
                assertEquals(2, late.toBlock().process(1), "the same declaration works once the flag is cleared")
            }
        }
    }
}

package dev.prime.optimus

import dev.prime.CoreClosedException
import dev.prime.PrimeException
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.function.Executable

/**
 * Runs [action] with the calling thread's interrupt flag set, while Redis is unreachable, and
 * checks how it fails: a [PrimeException] that says it was interrupted and names [named] (quoted,
 * as messages name things), never [CoreClosedException] (the core is open), the flag kept (and
 * cleared here). Returns the failure.
 */
internal fun assertInterruptedInOutage(what: String, named: String, action: () -> Unit): PrimeException {
    Thread.currentThread().interrupt()
    val failure = try {
        assertThrows(PrimeException::class.java, Executable { action() }, what)
    } finally {
        assertTrue(Thread.interrupted(), "$what: the flag is kept (and cleared here)")
    }
    assertFalse(failure is CoreClosedException, "$what: the core is open: $failure")
    assertTrue(failure.message!!.contains("interrupted"), "$what: says why: ${failure.message}")
    assertTrue(failure.message!!.contains("'$named'"), "$what: names '$named': ${failure.message}")
    return failure
}

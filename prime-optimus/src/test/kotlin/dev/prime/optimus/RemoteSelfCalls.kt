package dev.prime.optimus

import dev.prime.Block
import dev.prime.ChainFailedException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertInstanceOf
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import java.time.Duration

/**
 * Calls [outer], a block of chain `counter` whose service runs in another process, with 0 (no
 * call from inside) and with [reentering] (its block calls its own chain): the second fails at
 * once, well before the 60 s call timeout, with a [ChainFailedException] naming `counter` whose
 * [RemoteFailureException] carries the refusal's `IllegalStateException`; then the chain serves
 * the next call.
 */
internal fun assertRefusedFromInsideItselfInAnotherProcess(outer: Block<Int, Int>, reentering: Int) {
    assertEquals(0, outer.process(0), "a call that does not call the chain from inside")
    val began = System.nanoTime()
    val failure = assertThrows(ChainFailedException::class.java) { outer.process(reentering) }
    assertTrue(
        System.nanoTime() - began < Duration.ofSeconds(10).toNanos(),
        "refused at once, not by the call timeout of 60 s",
    )
    assertEquals("counter", failure.chainName(), failure.toString())
    val remote = assertInstanceOf(RemoteFailureException::class.java, failure.cause)
    assertTrue("IllegalStateException" in remote.message!!, remote.message)
    assertTrue("called from inside itself" in remote.message!!, remote.message)
    assertEquals(0, outer.process(0), "the chain serves the next call")
}

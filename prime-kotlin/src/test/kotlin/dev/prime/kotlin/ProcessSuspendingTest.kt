package dev.prime.kotlin

import dev.prime.Block
import kotlinx.coroutines.isActive
import kotlinx.coroutines.runBlocking
import org.junit.jupiter.api.Assertions.assertInstanceOf
import org.junit.jupiter.api.Assertions.assertSame
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import kotlin.coroutines.EmptyCoroutineContext

/** `processSuspending` of a plain block, with no core: what its KDoc says of a call that was not cancelled. */
internal class ProcessSuspendingTest {

    /**
     * A block interrupted by something other than the call's cancellation (its own code, an
     * executor shutting down) fails: the call reaches the caller with the block's
     * `InterruptedException`, as the block threw it, not as a cancellation the coroutine never had
     * (which a `launch` would drop without a word).
     */
    @Test
    fun `a block interrupted while its call is not cancelled fails the call with its InterruptedException`(): Unit = runBlocking {
        val interrupted = InterruptedException("the block's own interrupt")
        val block = Block<Int, Int> { throw interrupted }
        for (context in listOf(kotlinx.coroutines.Dispatchers.IO, EmptyCoroutineContext)) {
            val failure = runCatching { block.processSuspending(1, context) }.exceptionOrNull()
            assertTrue(isActive, "the calling coroutine was cancelled")
            assertInstanceOf(InterruptedException::class.java, failure, "what the call on $context threw")
            assertSame(interrupted, failure, "the block's own exception")
        }
    }

    /** An interrupt the block meets in a blocking wait, not the cancellation's, also fails the call with it. */
    @Test
    fun `a block that meets an interrupt in a wait fails the call with its InterruptedException`(): Unit = runBlocking {
        val block = Block<Int, Int> { x ->
            Thread.currentThread().interrupt()
            Thread.sleep(WAIT_MILLIS)
            x
        }
        val failure = runCatching { block.processSuspending(1) }.exceptionOrNull()
        assertTrue(isActive, "the calling coroutine was cancelled")
        assertInstanceOf(InterruptedException::class.java, failure, "what the call threw")
    }

    private companion object {
        const val WAIT_MILLIS = 20_000L
    }
}

package dev.prime.optimus

import java.time.Duration
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicBoolean

/**
 * Holds a service inside its block while a test changes Redis under it: the first block to call
 * [hold] waits there until the test calls [open]; any later call passes at once (a block run
 * again for the same value does not wait a second time). Every wait is bounded by [patience].
 */
internal class BlockGate(private val patience: Duration = Duration.ofSeconds(20)) {
    private val entered = CountDownLatch(1)
    private val released = CountDownLatch(1)
    private val taken = AtomicBoolean()

    /** Called in the block: the first caller says it is in, then waits for [open]; fails the block if none comes in time. */
    fun hold() {
        if (!taken.compareAndSet(false, true)) return
        entered.countDown()
        check(released.await(patience.seconds, TimeUnit.SECONDS)) { "the test did not release the block within $patience" }
    }

    /** Whether a block came to [hold] within [within]. */
    fun awaitHeld(within: Duration = patience): Boolean = entered.await(within.toMillis(), TimeUnit.MILLISECONDS)

    /** Lets the held block (and every later one) go on. */
    fun open() = released.countDown()
}

package dev.prime.optimus

import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertNotNull
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicReference

/**
 * A block of one core that left its thread's interrupt flag set calls a chain of another open
 * core of this JVM: the call is made as if the flag were not set (the kit checks that it gets
 * its result), yet a close of either core still ends the call, long before the call timeout: the
 * called core's close closes the call's connections, the calling core's interrupts the call at once.
 */
class CrossCoreFlagTest {

    @Test
    fun aCloseOfTheCalledCoreEndsTheCall() = assertACloseEndsTheCall(closeCaller = false)

    @Test
    fun aCloseOfTheCallingCoreEndsTheCall() = assertACloseEndsTheCall(closeCaller = true)

    private fun assertACloseEndsTheCall(closeCaller: Boolean) {
        val inside = CountDownLatch(1)
        val release = CountDownLatch(1)
        val ended = CountDownLatch(1)
        val thrown = AtomicReference<Throwable>()
        try {
            TestRedis.core().use { called ->
                TestRedis.core().use { calling ->
                    val slow = called.chain("slow") { x: Int ->
                        inside.countDown()
                        release.await(PATIENCE_SECONDS, TimeUnit.SECONDS)
                        x
                    }.toBlock()
                    called.start()
                    val events = EventBlock<Int>()
                    calling.source("flagged-events", events).then(
                        calling.chain("flagged-caller") { x: Int ->
                            Thread.currentThread().interrupt()
                            try {
                                slow.process(x)
                            } catch (e: Throwable) {
                                thrown.set(e)
                                throw e
                            } finally {
                                ended.countDown()
                            }
                        },
                    ).reader()
                    calling.start()
                    events.publish(1)
                    assertTrue(inside.await(PATIENCE_SECONDS, TimeUnit.SECONDS), "the called block runs: the flag did not fail the call")
                    (if (closeCaller) calling else called).close()
                    assertTrue(ended.await(PATIENCE_SECONDS, TimeUnit.SECONDS), "the close ended the call")
                    assertNotNull(thrown.get(), "the call failed")
                    release.countDown()
                }
            }
        } finally {
            release.countDown()
        }
    }

    private companion object {
        /** Far below the default call timeout (60 s): a call that ends within it ended with the close. */
        const val PATIENCE_SECONDS = 20L
    }
}

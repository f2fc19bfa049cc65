package dev.prime.optimus

import dev.prime.EventBlock
import dev.prime.PrimeCore
import dev.prime.Reader
import dev.prime.liberty.LibertyCore
import dev.prime.radiant.RadiantCore
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNotNull
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration
import java.util.concurrent.CopyOnWriteArrayList
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicReference

/**
 * A block of a Liberty or Radiant core's service (in the same JVM) that left its thread's interrupt
 * flag set and calls an Optimus chain's `toBlock()` gets its result, as it would calling a chain of
 * its own media (run inline): the thread is a core's own, whose flag its service clears after the
 * block; the flag is set again after the call. A close of the calling core still ends the call.
 */
class OtherMediaFlagTest {

    @Test
    fun aLibertyServiceThatInterruptedItsThreadGetsTheResultOfAnOptimusChain() = assertTheCallSucceeds(LibertyCore())

    @Test
    fun aRadiantServiceThatInterruptedItsThreadGetsTheResultOfAnOptimusChain() = assertTheCallSucceeds(RadiantCore())

    @Test
    fun aCloseOfTheLibertyCoreStillEndsItsServicesCall() = assertACloseEndsTheCall(LibertyCore())

    @Test
    fun aCloseOfTheRadiantCoreStillEndsItsServicesCall() = assertACloseEndsTheCall(RadiantCore())

    private fun assertTheCallSucceeds(calling: PrimeCore) {
        val seen = CopyOnWriteArrayList<String>()
        val failures = CopyOnWriteArrayList<Throwable>()
        TestRedis.core().use { optimus ->
            calling.use {
                val callee = optimus.chain("callee") { x: Int -> x + 1 }.toBlock()
                optimus.start()
                val events = EventBlock<Int>()
                val results: Reader<Int> = calling.source("flagged-events", events).then(
                    calling.chain("flagged-caller") { x: Int ->
                        Thread.currentThread().interrupt()
                        try {
                            callee.process(x).also {
                                seen += "$x" + if (Thread.currentThread().isInterrupted) " flagged after" else ""
                            }
                        } catch (e: Throwable) {
                            failures += e
                            throw e
                        }
                    },
                ).reader()
                calling.start()
                events.publish(1)
                events.publish(2)
                val got = listOf(results.take(PATIENCE).orElse(null), results.take(PATIENCE).orElse(null))
                assertEquals(listOf<Throwable>(), failures, "no call failed")
                assertEquals(listOf(2, 3), got, "each value's call to the Optimus chain got its result")
                assertEquals(listOf("1 flagged after", "2 flagged after"), seen, "the flag is set again after the call")
            }
        }
    }

    private fun assertACloseEndsTheCall(calling: PrimeCore) {
        val inside = CountDownLatch(1)
        val release = CountDownLatch(1)
        val ended = CountDownLatch(1)
        val thrown = AtomicReference<Throwable>()
        try {
            TestRedis.core().use { optimus ->
                calling.use {
                    val slow = optimus.chain("slow") { x: Int ->
                        inside.countDown()
                        release.await(PATIENCE_SECONDS, TimeUnit.SECONDS)
                        x
                    }.toBlock()
                    optimus.start()
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
                    calling.close()
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
        const val PATIENCE_SECONDS = 20L
        val PATIENCE: Duration = Duration.ofSeconds(PATIENCE_SECONDS)
    }
}

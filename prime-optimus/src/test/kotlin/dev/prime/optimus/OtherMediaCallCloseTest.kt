package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.PrimeCore
import dev.prime.liberty.LibertyCore
import dev.prime.radiant.RadiantCore
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * A close of an Optimus core whose service's block is in a call of a Liberty or Radiant core's
 * chain (same JVM) whose block waits (interruptibly) ends that call at once and returns long
 * before its `shutdownTimeout`, as a close of a Liberty or Radiant core does for a call of another
 * core's chain: the called block runs inline, on the service's thread.
 */
class OtherMediaCallCloseTest {

    @Test
    fun aCloseOfAnOptimusCoreEndsItsServicesCallOfALibertyChain() =
        assertACloseEndsTheCall { LibertyCore(it) }

    @Test
    fun aCloseOfAnOptimusCoreEndsItsServicesCallOfARadiantChain() =
        assertACloseEndsTheCall { RadiantCore(it) }

    private fun assertACloseEndsTheCall(newCallee: (CoreConfig) -> PrimeCore) {
        val inside = CountDownLatch(1)
        val release = CountDownLatch(1)
        val closed = CountDownLatch(1)
        val config = CoreConfig.builder().shutdownTimeout(PATIENCE.multipliedBy(3)).build()
        try {
            newCallee(config).use { other ->
                TestRedis.core(config).use { optimus ->
                    val waiting = other.chain("other-media-waiting") { x: Int ->
                        inside.countDown()
                        try {
                            release.await(PATIENCE_SECONDS * 4, TimeUnit.SECONDS)
                        } catch (_: InterruptedException) {
                            Thread.currentThread().interrupt()
                        }
                        x
                    }.toBlock()
                    other.start()
                    val events = EventBlock<Int>()
                    optimus.source("closing-caller-events", events)
                        .then(optimus.chain("closing-caller") { x: Int -> waiting.process(x) })
                        .reader()
                    optimus.start()
                    events.publish(1)
                    assertTrue(inside.await(PATIENCE_SECONDS, TimeUnit.SECONDS), "the other core's block runs")
                    val closer = Thread({
                        optimus.close()
                        closed.countDown()
                    }, "closing-caller-closer")
                    closer.isDaemon = true
                    closer.start()
                    assertTrue(
                        closed.await(PATIENCE_SECONDS, TimeUnit.SECONDS),
                        "close() returned within $PATIENCE, though its service's block was in a call of " +
                            "${other.javaClass.simpleName}'s chain (shutdownTimeout ${config.shutdownTimeout()})",
                    )
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

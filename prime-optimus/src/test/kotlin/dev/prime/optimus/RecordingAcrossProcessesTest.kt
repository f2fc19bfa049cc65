package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.PrimeCore
import dev.prime.RecordedValue
import dev.prime.Recording
import dev.prime.RecordingOptions
import dev.prime.Source
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration
import java.util.Optional
import java.util.UUID

/**
 * Each process of an Optimus topology records what runs in it: the publisher records the values
 * its event block publishes, the worker the outputs of the chain it hosts; merged, the recordings
 * hold both, each output after the tick it came from. (Two cores of one JVM on one Redis, hosting
 * apart, stand for two processes, as the other multi-host tests do.)
 */
class RecordingAcrossProcessesTest {

    @Test
    fun eachProcessRecordsWhatItRunsAndTheRecordingsMerge() {
        val config = CoreConfig.builder().name("rec-" + UUID.randomUUID())
            .recording(RecordingOptions.ring(100)).build()
        val ticks = EventBlock<Int>()
        OptimusCore.builder().config(config).redis(TestRedis.url).hosts(emptyList()).build().use { publisher ->
            val out = declare(publisher, ticks).reader()
            OptimusCore.builder().config(config).redis(TestRedis.url).hosts("odometry").build().use { worker ->
                declare(worker, EventBlock())
                worker.start()
                publisher.start()
                for (i in 1..COUNT) ticks.publish(i)
                repeat(COUNT) { i ->
                    assertEquals(Optional.of(10 * (i + 1)), out.take(Duration.ofSeconds(PATIENCE_S)))
                }

                val here: Recording = publisher.recording()
                val there: Recording = worker.recording()
                assertEquals((1..COUNT).toList(), here.getAll<Int>("ticks"))
                assertEquals(Optional.empty<Int>(), here.tryGet<Int>("odometry"), "not hosted by the publisher")
                assertEquals(emptyList<Int>(), there.getAll<Int>("ticks"), "the worker published nothing")
                assertEquals((1..COUNT).map { it * 10 }, there.getAll<Int>("odometry"))
                assertEquals((0L until COUNT.toLong()).toList(),
                    there.getAllStamped<Int>("odometry").map(RecordedValue<Int>::sequence))

                val merged = Recording.merge(here, there)
                val tickTimes = merged.getAllStamped<Int>("ticks")
                val outputs = merged.getAllStamped<Int>("odometry")
                assertEquals(COUNT, tickTimes.size)
                assertEquals(COUNT, outputs.size)
                for (i in 0 until COUNT) {
                    assertEquals(tickTimes[i].value() * 10, outputs[i].value())
                    assertFalse(outputs[i].wallTime().isBefore(tickTimes[i].wallTime()),
                        "output ${outputs[i]} recorded before its tick ${tickTimes[i]}")
                }
                assertTrue(merged.names().containsAll(listOf("ticks", "odometry")))
            }
        }
    }

    private fun declare(core: PrimeCore, ticks: EventBlock<Int>): Source<Int> =
        core.source("ticks", ticks).then(core.chain("odometry") { t: Int -> t * 10 })

    private companion object {
        const val COUNT = 20
        const val PATIENCE_S = 30L
    }
}

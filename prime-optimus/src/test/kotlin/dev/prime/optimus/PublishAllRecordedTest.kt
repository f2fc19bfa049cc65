package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.QueueFullException
import dev.prime.RecordingOptions
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration
import java.util.UUID

/**
 * Values given to [OptimusCore.publishAll] are published by their source like those of its event
 * block: with recording on they are recorded under the source (architecture.md, "Recording what a
 * controller does": every value an `EventSource` publishes, after the media accepted it; "What
 * every media keeps", *Recording*), and with metrics on the source counts them in and out ("every
 * event source (in = publishes, out = publishes the media accepted)").
 */
class PublishAllRecordedTest {

    @Test
    fun valuesPublishedAllAtOnceAreRecordedAndCountedLikeThoseOfTheEventBlock() {
        val config = CoreConfig.builder().name("publish-all-recorded-" + UUID.randomUUID())
            .recording(RecordingOptions.ring(100)).metrics(true).build()
        TestRedis.core(config).use { core ->
            val events = EventBlock<Int>()
            val numbers = core.source("numbers", events)
            val reader = numbers.reader()
            core.start()
            events.publish(1)
            core.publishAll(numbers, listOf(2, 3, 4))
            events.publish(5)
            assertEquals(listOf(1, 2, 3, 4, 5), (1..5).map { reader.take(PATIENCE).orElseThrow() })

            val recording = core.recording()
            assertEquals(listOf(1, 2, 3, 4, 5), recording.getAll<Int>("numbers"), "what the source published")
            val stamped = recording.getAllStamped<Int>("numbers")
            assertEquals((0L..4L).toList(), stamped.map { it.sequence() }, "gap-free sequence numbers")
            for (i in 1 until stamped.size) {
                assertTrue(
                    !stamped[i].wallTime().isBefore(stamped[i - 1].wallTime()) &&
                        stamped[i].monotonicNanos() >= stamped[i - 1].monotonicNanos(),
                    "stamps grow with the sequence numbers: $stamped",
                )
            }
            val metered = core.metrics().service("numbers")
            assertEquals(5, metered.valuesIn(), "publishes counted in: $metered")
            assertEquals(5, metered.valuesOut(), "publishes the media accepted counted out: $metered")
        }
    }

    /**
     * A `publishAll` the media refuses (more values than a service's queue limit: refused at once)
     * published nothing, so nothing of it is recorded, and the source counts its values in but not
     * out, as for a refused publish of its event block.
     */
    @Test
    fun aRefusedPublishAllIsNotRecordedAndCountsInButNotOut() {
        val config = CoreConfig.builder().name("publish-all-refused-" + UUID.randomUUID())
            .recording(RecordingOptions.ring(100)).metrics(true).build()
        OptimusCore.builder().config(config).redis(TestRedis.url).queueLimit(2).build().use { core ->
            val numbers = core.source("numbers", EventBlock<Int>())
            val doubled = numbers.then(core.chain("double") { x: Int -> 2 * x }).reader()
            core.start()
            assertThrows(QueueFullException::class.java) { core.publishAll(numbers, listOf(1, 2, 3)) }
            assertEquals(listOf<Int>(), core.recording().getAll<Int>("numbers"), "a refused publish is not recorded")
            core.publishAll(numbers, listOf(4, 5))
            assertEquals(listOf(8, 10), (1..2).map { doubled.take(PATIENCE).orElseThrow() })
            assertEquals(listOf(4, 5), core.recording().getAll<Int>("numbers"))
            val metered = core.metrics().service("numbers")
            assertEquals(5, metered.valuesIn(), "every value given counted in: $metered")
            assertEquals(2, metered.valuesOut(), "only the accepted ones out: $metered")
        }
    }

    private companion object {
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

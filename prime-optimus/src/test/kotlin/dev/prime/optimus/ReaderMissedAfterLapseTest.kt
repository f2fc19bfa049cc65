package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration

/**
 * `Reader.missed()` is the count since the reader was made: a reader whose process was cut off
 * longer than its lease, reclaimed by another process and declared again when its process came
 * back, keeps counting from where it was; a dead instance's counter does not stay for ever.
 */
class ReaderMissedAfterLapseTest {

    @Test
    fun aReaderDeclaredAgainAfterItsLeaseLapsedKeepsItsMissedCount() {
        CutOffReaderRig(CoreConfig.builder().name("missed-${System.nanoTime()}").sourceRetention(10).build()).use { rig ->
            val reader = rig.readerCore.source("numbers", EventBlock<Int>()).reader() as OptimusReader<Int>
            rig.readerCore.start()
            // one value per publish: the reader falls 20 values behind a retention of 10
            (1..30).forEach { rig.publisher.publishAll(rig.numbers, listOf(it)) }
            assertEquals(20L, reader.missed(), "the reader missed 20 values before its lease lapsed")

            rig.cutOffUntilReclaimed()
            val missedKey = rig.keys.missedOf(reader.list)
            val kept = rig.raw.pttl(missedKey)
            assertTrue(kept in 1..Liveness.MISSED_KEPT_MILLIS, "the reclaim keeps the count for a while, not for ever (PTTL $kept ms)")
            rig.proxy.restore()
            rig.awaitReaders(1, "the reader's process declared it again")

            assertEquals(20L, reader.missed(), "the count goes on from where it was")
            assertEquals(-1L, rig.raw.pttl(missedKey), "declared again, the reader's count is kept as long as the reader")
            assertEquals((21..30).toList(), (21..30).map { reader.take(Duration.ofSeconds(10)).orElseThrow() }, "the retained values")
        }
    }
}

package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import java.time.Duration

/**
 * A reader whose process was cut off longer than its lease is reclaimed by another process, and
 * registered again when its process comes back: the registration copies the whole retained log
 * into its list. With a retention larger than the default number of ids a reader remembers
 * (4096), the values it had handed out must still not come out again.
 */
class ReaderLapseRetentionTest {

    @Test
    fun aReaderRegisteredAgainAfterItsLeaseLapsedDeliversNothingTwiceWithALargeRetention() {
        val retention = 6000
        CutOffReaderRig(CoreConfig.builder().name("lapse-${System.nanoTime()}").sourceRetention(retention).build()).use { rig ->
            val reader = rig.readerCore.source("numbers", EventBlock<Int>()).reader()
            rig.readerCore.start()
            (1..retention).chunked(200).forEach { rig.publisher.publishAll(rig.numbers, it) }
            val received = ArrayList<Int>()
            repeat(retention) { received += reader.take(Duration.ofSeconds(10)).orElseThrow() }
            assertEquals((1..retention).toList(), received)

            rig.cutOffUntilReclaimed()
            rig.proxy.restore()
            rig.awaitReaders(1, "the reader's process registered it again")

            rig.publisher.publishAll(rig.numbers, listOf(retention + 1))
            assertEquals(
                retention + 1,
                reader.take(Duration.ofSeconds(10)).orElse(null),
                "the next value comes first: none of the values handed out before the lapse came out again",
            )
            assertEquals(emptyList<Int>(), reader.drain(), "nothing more")
        }
    }
}

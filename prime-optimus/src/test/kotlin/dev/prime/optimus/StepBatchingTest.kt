package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.Reader
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import java.time.Duration

/** The step script stores values for one list in chunks of 1000 pushes: nothing lost or reordered at the edges. */
class StepBatchingTest {

    @Test
    fun aPublishedBatchLargerThanOneChunkReachesEveryReaderWholeAndInOrder() {
        TestRedis.core(CoreConfig.builder().sourceRetention(10_000).build()).use { core ->
            val input = core.source(EventBlock<Int>())
            val direct = input.reader()
            val chained = input.then(core.link(core.chain("plus") { x: Int -> x + 1 }, core.chain("twice") { x: Int -> 2 * x })).reader()
            core.start()
            val values = (0 until 2501).toList()
            core.publishAll(input, values)
            assertEquals(values, takeAll(direct, values.size))
            assertEquals(values.map { 2 * (it + 1) }, takeAll(chained, values.size))
            assertEquals(0L, direct.missed())
            assertEquals(0L, chained.missed())
        }
    }

    @Test
    fun oneInputMakingMoreValuesThanOneChunkPublishesThemAllInOrder() {
        TestRedis.core(CoreConfig.builder().sourceRetention(10_000).build()).use { core ->
            val events = EventBlock<Int>()
            val out = core.source(events).flatMap<Int> { n: Int -> (0 until n).toList() }
                .then(core.chain("negate") { x: Int -> -x }).reader()
            core.start()
            events.publish(2001)
            assertEquals((0 until 2001).map { -it }, takeAll(out, 2001))
        }
    }

    private fun takeAll(reader: Reader<Int>, count: Int): List<Int> =
        List(count) { reader.take(Duration.ofSeconds(30)).orElseThrow() }
}

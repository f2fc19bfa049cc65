package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.liberty.LibertyCore
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration

/**
 * Optimus's codec given to an in-memory media: `copyValues(KryoCodec.standard())` makes a Liberty
 * test fail the way Optimus would, on a mutation after publish and on a type the codec does not know.
 */
class KryoCopyValuesTest {

    /** A mutable class no codec registered. */
    class Unregistered(var count: Int)

    private fun liberty(codec: KryoCodec) = LibertyCore(CoreConfig.builder().copyValues(codec).build())

    @Test
    fun aReaderDoesNotSeeAMutationAfterPublish() {
        liberty(KryoCodec.standard()).use { core ->
            val events = EventBlock<MutableList<Int>>()
            val reader = core.source(events).reader()
            core.start()
            val value = arrayListOf(1, 2)
            events.publish(value)
            value += 3
            assertEquals(listOf(1, 2), reader.take(Duration.ofSeconds(20)).orElseThrow())
        }
    }

    @Test
    fun aTypeKryoDoesNotKnowIsRefusedAsOnOptimus() {
        liberty(KryoCodec.standard()).use { core ->
            val events = EventBlock<Unregistered>()
            core.source(events)
            val chain = core.chain("count") { u: Unregistered -> u.count }
            core.start()
            val published = assertThrows(IllegalArgumentException::class.java) { events.publish(Unregistered(1)) }
            assertTrue(published.message!!.contains("allow(KryoCopyValuesTest.Unregistered.class)"), published.message)
            val block = chain.toBlock()
            assertThrows(IllegalArgumentException::class.java) { block.process(Unregistered(1)) }
        }
    }

    @Test
    fun aRegisteredTypeIsCopied() {
        liberty(KryoCodec.builder().register(Unregistered::class.java).build()).use { core ->
            val chain = core.chain("grow") { u: Unregistered -> u.apply { count++ } }
            core.start()
            val input = Unregistered(1)
            val output = chain.toBlock().process(input)
            assertEquals(2, output.count)
            assertEquals(1, input.count, "the block changed the caller's value")
        }
    }
}

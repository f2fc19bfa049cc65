package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.conformance.CapturedStderr
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration

/**
 * A codec of the user's that breaks its contract (it throws something else than [CodecException]
 * for a value it cannot decode) costs a reader that value only, as a [CodecException] does: the
 * reader logs a WARN naming the value's id and the codec's exception, and hands out the next
 * value; nothing is skipped without that line.
 */
class ReaderCodecFailureTest {

    /** The standard codec, except that it throws [IllegalStateException] for the string "poison". */
    private class Breaking : OptimusCodec by KryoCodec.standard() {
        private val standard = KryoCodec.standard()

        override fun decode(bytes: ByteArray): Any =
            standard.decode(bytes).also { check(it != "poison") { "this codec cannot read poison" } }
    }

    private fun withReader(name: String, test: (EventBlock<String>, dev.prime.Reader<String>) -> Unit) {
        val config = CoreConfig.builder().name("$name-${System.nanoTime()}").build()
        OptimusCore.builder().config(config).redis(TestRedis.url).codec(Breaking()).build().use { core ->
            val events = EventBlock<String>()
            val reader = core.source("words", events).reader()
            core.start()
            listOf("a", "poison", "c").forEach(events::publish) // three entries
            test(events, reader)
        }
    }

    @Test
    fun aDrainSkipsAValueTheCodecFailsOnWithAWarningAndReturnsTheRest() {
        val lines = CapturedStderr().use { err ->
            withReader("codec-breaks-drain") { _, reader ->
                // the three values are in the reader's list once the publishes returned
                val received = ArrayList<String>()
                repeat(3) { received += reader.drain() }
                assertEquals(listOf("a", "c"), received, "the values the codec reads, in order")
            }
            err.lines().filter { "skipped a value" in it }
        }
        assertEquals(1, lines.size, "one WARN for the value the codec failed on: $lines")
        assertTrue(" WARN " in lines[0] && "IllegalStateException" in lines[0] && "cannot read poison" in lines[0], lines[0])
        assertTrue(Regex("value id -?\\d+").containsMatchIn(lines[0]), "the line names the value: ${lines[0]}")
    }

    @Test
    fun aTakeSkipsAValueTheCodecFailsOnAndHandsOutTheNext() {
        withReader("codec-breaks-take") { events, reader ->
            assertEquals("a", reader.take(PATIENCE).orElseThrow())
            assertEquals("c", reader.take(PATIENCE).orElseThrow(), "the value after the one the codec failed on")
            events.publish("d")
            assertEquals("d", reader.take(PATIENCE).orElseThrow(), "the reader goes on")
        }
    }

    private companion object {
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

package dev.prime.optimus

import dev.prime.ChainFailedException
import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration

/**
 * A codec of the user's that breaks its contract (it throws something else than [CodecException]
 * for a value it cannot decode) costs a service that value only, as a [CodecException] does: the
 * value is dead-lettered with the codec's exception (a caller gets an error reply), and the
 * service goes on with the values behind it.
 */
class ServiceCodecFailureTest {

    /** The standard codec, except that it throws [IllegalStateException] for the string "poison". */
    private class Breaking : OptimusCodec by KryoCodec.standard() {
        private val standard = KryoCodec.standard()

        override fun decode(bytes: ByteArray): Any =
            standard.decode(bytes).also { check(it != "poison") { "this codec cannot read poison" } }
    }

    private fun core(name: String): OptimusCore {
        val config = CoreConfig.builder().name("$name-${System.nanoTime()}").build()
        return OptimusCore.builder().config(config).redis(TestRedis.url).codec(Breaking()).callTimeout(PATIENCE).build()
    }

    @Test
    fun aValueTheCodecFailsOnIsDeadLetteredAndTheServiceGoesOn() {
        core("service-codec-breaks").use { core ->
            val events = EventBlock<String>()
            val out = core.source("words", events).then(core.chain("upper") { x: String -> x.uppercase() }).reader()
            core.start()
            events.publish("poison")
            events.publish("ok")
            assertEquals("OK", out.take(PATIENCE).orElseThrow { AssertionError("the value behind the one the codec failed on did not arrive") })
            val letters = core.deadLetters("upper")
            assertEquals(1, letters.size, letters.toString())
            assertTrue("IllegalStateException" in letters[0].reason && "cannot read poison" in letters[0].reason, letters[0].reason)
        }
    }

    @Test
    fun aCallTheCodecFailsOnGetsAnErrorReplyAndTheServiceGoesOn() {
        core("call-codec-breaks").use { core ->
            val upper = core.chain("upper") { x: String -> x.uppercase() }.toBlock()
            core.start()
            val e = assertThrows(ChainFailedException::class.java) { upper.process("poison") }
            assertTrue("cannot read poison" in e.cause.toString(), e.cause.toString())
            assertEquals("OK", upper.process("ok"), "the service goes on")
        }
    }

    private companion object {
        val PATIENCE: Duration = Duration.ofSeconds(10)
    }
}

package dev.prime.optimus

import dev.prime.CoreConfig
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/** Processes of one topology must agree on the codec; a disagreeing one is refused at start. */
class CodecAgreementTest {

    /** The standard codec under another fingerprint: stands for a process with other registrations. */
    private class Renamed(private val fingerprint: String) : OptimusCodec by KryoCodec.standard() {
        override fun fingerprint(): String = fingerprint
    }

    @Test
    fun aProcessWithAnotherCodecIsRefusedAtStart() {
        val config = CoreConfig.builder().name("codec-agreement").build()
        OptimusCore.builder().config(config).redis(TestRedis.url).codec(Renamed("alpha")).build().use { first ->
            first.start()
            OptimusCore.builder().config(config).redis(TestRedis.url).codec(Renamed("alpha")).build().use { same ->
                same.start() // agrees
            }
            OptimusCore.builder().config(config).redis(TestRedis.url).codec(Renamed("beta")).build().use { other ->
                val e = assertThrows(IllegalStateException::class.java) { other.start() }
                assertTrue(e.message!!.contains("alpha") && e.message!!.contains("beta"), e.message)
                assertTrue(e.message!!.contains("allow the same types"), e.message)
            }
        }
    }

    /** A type nobody registered. */
    private data class Unregistered(val x: Int)

    @Test
    fun aValueOfATypeTheCodecRefusesFailsTheCallerWithHowToRegisterIt() {
        TestRedis.core().use { core ->
            val echo = core.chain("echo") { x: Any -> x }.toBlock()
            core.start()
            val e = assertThrows(IllegalArgumentException::class.java) { echo.process(Unregistered(1)) }
            assertTrue(e.message!!.contains("Unregistered") && e.message!!.contains(".allow(CodecAgreementTest.Unregistered.class)"), e.message)
            assertEquals("fine", echo.process("fine"), "the service is untouched")
        }
    }
}

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

    @Test
    fun aPublishOfATypeTheDefaultCodecRefusesSaysWhichLineToAdd() {
        TestRedis.core().use { core ->
            val events = dev.prime.EventBlock<Any>()
            val reader = core.source("readings", events).reader()
            core.start()
            val e = assertThrows(IllegalArgumentException::class.java) { events.publish(Unregistered(1)) }
            assertEquals(
                "KryoCodec cannot encode a value of type dev.prime.optimus.CodecAgreementTest\$Unregistered: the type " +
                    "is not allowed (records and enums are accepted without configuration; Unregistered is neither). " +
                    "Allow it where the codec is built: KryoCodec.builder().allow(CodecAgreementTest.Unregistered.class) " +
                    "(Kotlin: allow(CodecAgreementTest.Unregistered::class.java)), or allow its whole package: " +
                    "KryoCodec.builder().allowPackage(\"dev.prime.optimus\"). Every process of the topology must allow " +
                    "the same types",
                e.message,
            )
            events.publish(Pose(1.0, 2.0, 3.0)) // a record: taken without configuration
            assertEquals(Pose(1.0, 2.0, 3.0), reader.take(java.time.Duration.ofSeconds(20)).orElseThrow(), "nothing else was published")
        }
    }
}

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

    /** A codec that is not a [KryoCodec]: it records the size of every array it is asked to decode. */
    private class Recording : OptimusCodec by KryoCodec.standard() {
        val decoded: MutableList<Int> = java.util.Collections.synchronizedList(ArrayList())

        override fun decode(bytes: ByteArray): Any {
            decoded += bytes.size
            return KryoCodec.standard().decode(bytes)
        }
    }

    @Test
    fun aCodecOfTheUsersOwnGetsExactlyTheValuesBytesOnEveryPath() {
        val codec = Recording()
        val sizes = setOf("ab", "abab").map { KryoCodec.standard().encode(it).size }.toSet()
        OptimusCore.builder().config(CoreConfig.builder().name("own-codec").build()).redis(TestRedis.url).codec(codec).build().use { core ->
            val events = dev.prime.EventBlock<String>()
            val out = core.link(core.source("in", events), core.chain("double") { x: String -> x + x }).reader()
            val echo = core.chain("echo") { x: String -> x }.toBlock()
            core.start()
            assertEquals("ab", echo.process("ab"), "a call: the service decodes the request, the caller the reply")
            events.publish("ab")
            assertEquals("abab", out.take(java.time.Duration.ofSeconds(20)).orElseThrow(), "a service and a reader decode the values")
            assertEquals(sizes, codec.decoded.toSet(), "sizes of the arrays decoded: ${codec.decoded}")
            assertTrue(codec.decoded.size >= 4, "decodes: ${codec.decoded}")
        }
    }

    @Test
    fun theKryoCodecDecodesAValueWhereItLiesAndOnlyThoseBytes() {
        val codec = KryoCodec.standard()
        val bytes = codec.encode("a value")
        val embedded = ByteArray(5) { 7 } + bytes + ByteArray(7) { 9 }
        assertEquals("a value", codec.decode(embedded, 5, bytes.size))
        val short = assertThrows(CodecException::class.java) { codec.decode(embedded, 5, bytes.size - 1) }
        assertTrue(short.message!!.startsWith("KryoCodec cannot decode ${bytes.size - 1} bytes"), short.message)
        val long = assertThrows(CodecException::class.java) { codec.decode(embedded, 5, bytes.size + 1) }
        assertTrue(long.message!!.contains("1 bytes are left over"), long.message)
    }
}

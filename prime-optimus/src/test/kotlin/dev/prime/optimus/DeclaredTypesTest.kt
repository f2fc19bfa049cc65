package dev.prime.optimus

import com.acme.robot.Note
import com.acme.robot.Reading
import dev.prime.Block
import dev.prime.CoreConfig
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Test

/**
 * A type the topology declares (a block class implementing `Block<I, O>`) and the codec refuses
 * fails `start()`; a record such a block declares is readable by its host before it sent one.
 */
internal class DeclaredTypesTest {

    /** Declares [Note], a Kotlin data class: neither record nor enum. */
    class Annotate : Block<Reading, Note> {
        override fun process(input: Reading): Note = Note("${input.sensor}=${input.value}")
    }

    /** Declares [Reading], a record. */
    class Calibrate : Block<Reading, Reading> {
        override fun process(input: Reading): Reading = input.copy(value = input.value * 2)
    }

    private fun core(name: String, codec: OptimusCodec? = null, hosts: Collection<String>? = null): OptimusCore {
        val builder = OptimusCore.builder().config(CoreConfig.builder().name(name).build()).redis(TestRedis.url)
            .callTimeout(java.time.Duration.ofSeconds(20))
        codec?.let(builder::codec)
        hosts?.let(builder::hosts)
        return builder.build()
    }

    @Test
    fun `a declared output type the default codec refuses fails start with the line to add`() {
        core("declared-note").use { core ->
            core.chain("annotate", Annotate())
            val e = assertThrows(IllegalStateException::class.java) { core.start() }
            assertEquals(
                "core 'declared-note' cannot start: service 'annotate' gives com.acme.robot.Note (Annotate implements " +
                    "Block<Reading, Note>), and KryoCodec does not allow it (records and enums are accepted without " +
                    "configuration; Note is neither). Allow it where the codec is built: " +
                    "KryoCodec.builder().allow(Note.class) (Kotlin: allow(Note::class.java)), or allow its whole " +
                    "package: KryoCodec.builder().allowPackage(\"com.acme.robot\"). Every process of the topology must " +
                    "allow the same types",
                e.message,
            )
        }
    }

    @Test
    fun `a strict codec refuses a declared record at start, and allowing its package lets the core start`() {
        core("declared-strict", KryoCodec.builder().learnRecordsAndEnums(false).build()).use { core ->
            core.chain("calibrate", Calibrate())
            val e = assertThrows(IllegalStateException::class.java) { core.start() }
            assertEquals(
                "core 'declared-strict' cannot start: service 'calibrate' takes com.acme.robot.Reading (Calibrate " +
                    "implements Block<Reading, Reading>), and KryoCodec does not allow it. Allow it where the codec " +
                    "is built: KryoCodec.builder().allow(Reading.class) (Kotlin: allow(Reading::class.java)), or allow " +
                    "its whole package: KryoCodec.builder().allowPackage(\"com.acme.robot\"). Every process of the " +
                    "topology must allow the same types",
                e.message,
            )
        }
        core("declared-allowed", KryoCodec.builder().learnRecordsAndEnums(false).allowPackage("com.acme.robot").build()).use { core ->
            val calibrate = core.chain("calibrate", Calibrate()).toBlock()
            core.start()
            assertEquals(Reading("gyro", 3.0), calibrate.process(Reading("gyro", 1.5)))
        }
    }

    @Test
    fun `with default codecs a host reads a record its block declares before it sent one`() {
        // Two cores of one topology on one Redis, each with its own default codec: the caller
        // sends a Reading, the host (which never sent one) must read it.
        core("declared-two", hosts = listOf("calibrate")).use { host ->
            host.chain("calibrate", Calibrate()).toBlock() // a chain's service is bound when it is used
            host.start()
            core("declared-two", hosts = emptyList()).use { caller ->
                val calibrate = caller.chain("calibrate", Calibrate()).toBlock()
                caller.start()
                assertEquals(Reading("gyro", 5.0), calibrate.process(Reading("gyro", 2.5)))
            }
            assertEquals(0, host.deadLetters("calibrate").size)
        }
    }
}

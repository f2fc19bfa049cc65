package dev.prime.optimus

import com.acme.robot.Command
import com.acme.robot.Mode
import com.acme.robot.Move
import com.acme.robot.Note
import com.acme.robot.Reading
import com.acme.robot.Stop
import com.acme.robot.TurnLeft
import com.acme.robot.inner.Hidden
import org.junit.jupiter.api.Assertions.assertArrayEquals
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNotEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/** Allowing types by package, by sealed hierarchy, and the records and enums a process sends. */
internal class KryoCodecAllowListTest {

    private val pkg = "com.acme.robot"

    private fun strict() = KryoCodec.builder().learnRecordsAndEnums(false)

    @Test
    fun `a package allows its records, enums and classes, read by a process that never sent one`() {
        val writer = strict().allowPackage(pkg).build()
        val reader = strict().allowPackage(pkg).build()
        for (value in listOf(Reading("gyro", 0.5), Mode.DRIVE, Note("n"), Move(2.0), listOf(Stop("s"), TurnLeft(45)))) {
            assertEquals(value, reader.decode(writer.encode(value)), value.toString())
        }
        assertEquals(writer.fingerprint(), reader.fingerprint())
    }

    @Test
    fun `a package does not allow its subpackages nor other packages, writing or reading`() {
        val codec = strict().allowPackage(pkg).build()
        val e = assertThrows(IllegalArgumentException::class.java) { codec.encode(Hidden("x")) }
        assertTrue(e.message!!.contains("allowPackage(\"com.acme.robot.inner\")"), e.message)
        val elsewhere = strict().allowPackage(Hidden::class.java.packageName).build().encode(Hidden("x"))
        val refused = assertThrows(CodecException::class.java) { codec.decode(elsewhere) }
        assertTrue(refused.message!!.contains("which this codec does not know"), refused.message)
    }

    @Test
    fun `ids do not depend on the order types are first sent in`() {
        val first = strict().allowPackage(pkg).build()
        val second = strict().allowPackage(pkg).build()
        val values = listOf(Reading("a", 1.0), Mode.IDLE, Move(3.0), Note("x"))
        val forward = values.map(first::encode)
        val backward = values.reversed().map(second::encode).reversed()
        forward.zip(backward).forEach { (a, b) -> assertArrayEquals(a, b) }
    }

    @Test
    fun `the order of declaration does not change the fingerprint nor the bytes`() {
        val ab = strict().allow(Pose::class.java).allow(Label::class.java).allowPackage(pkg).allowPackage("org.example").build()
        val ba = strict().allowPackage("org.example").allowPackage(pkg).allow(Label::class.java).allow(Pose::class.java).build()
        assertEquals(ab.fingerprint(), ba.fingerprint())
        assertEquals(ab.registeredTypes(), ba.registeredTypes())
        assertArrayEquals(ab.encode(Pose(1.0, 2.0, 3.0)), ba.encode(Pose(1.0, 2.0, 3.0)))
        assertEquals(Label("l", 1), ba.decode(ab.encode(Label("l", 1))))
    }

    @Test
    fun `the fingerprint tells apart other classes, packages and rules`() {
        val base = strict().allow(Pose::class.java).build().fingerprint()
        assertNotEquals(base, strict().allow(Label::class.java).build().fingerprint())
        assertNotEquals(base, strict().allow(Pose::class.java).allowPackage(pkg).build().fingerprint())
        assertNotEquals(base, KryoCodec.builder().allow(Pose::class.java).build().fingerprint())
        assertEquals(KryoCodec.standard().fingerprint(), KryoCodec.builder().build().fingerprint())
    }

    @Test
    fun `a sealed interface allows every concrete class it permits, through sealed subtypes`() {
        val codec = strict().allow(Command::class.java).build()
        val names = codec.registeredTypes().takeLast(3)
        assertEquals(listOf("100 ${Move::class.java.name}", "101 ${Stop::class.java.name}", "102 ${TurnLeft::class.java.name}"), names)
        for (value in listOf<Command>(Move(1.0), Stop("s"), TurnLeft(10))) assertEquals(value, codec.decode(codec.encode(value)))
        assertEquals(
            codec.fingerprint(),
            strict().allow(TurnLeft::class.java).allow(Stop::class.java).allow(Move::class.java).build().fingerprint(),
            "the same as allowing the classes one by one",
        )
        val e = assertThrows(IllegalArgumentException::class.java) { codec.encode(Reading("r", 1.0)) }
        assertTrue(e.message!!.startsWith("KryoCodec cannot encode a value of type ${Reading::class.java.name}: the type is not allowed."), e.message)
    }

    @Test
    fun `without configuration a process learns the records and enums it sends, and only those`() {
        val sender = KryoCodec.standard()
        val bytes = sender.encode(Reading("gyro", 1.0))
        assertEquals(Reading("gyro", 1.0), sender.decode(bytes), "the sender reads its own")
        assertEquals(Mode.IDLE, sender.decode(sender.encode(Mode.IDLE)))

        val other = KryoCodec.standard()
        val e = assertThrows(CodecException::class.java) { other.decode(bytes) }
        assertTrue(e.message!!.contains("learned only from values this process sends itself"), e.message)
        other.encode(Reading("other", 2.0))
        assertEquals(Reading("gyro", 1.0), other.decode(bytes), "once it sent one itself")

        assertThrows(IllegalArgumentException::class.java) { sender.encode(Note("a data class is not a record")) }
        assertThrows(IllegalArgumentException::class.java) { strict().build().encode(Reading("r", 0.0)) }
    }

    @Test
    fun `a package that is not the application's own is refused, and so is a malformed name`() {
        for (bad in listOf("java.util", "java", "javax.naming", "jdk.internal", "sun.misc", "kotlin.collections", "dev.prime", "dev.prime.optimus", "com.esotericsoftware.kryo")) {
            val e = assertThrows(IllegalArgumentException::class.java, { KryoCodec.builder().allowPackage(bad) }, bad)
            assertTrue(e.message!!.contains("not the application's own"), e.message)
        }
        for (bad in listOf("", "com..acme", "1com.acme", "com.acme.", "com.acme.*")) {
            val e = assertThrows(IllegalArgumentException::class.java, { KryoCodec.builder().allowPackage(bad) }, bad)
            assertTrue(e.message!!.contains("takes a package name"), e.message)
        }
        KryoCodec.builder().allowPackage("dev.prime.examples.robot") // an application under dev.prime
    }
}

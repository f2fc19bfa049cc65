package dev.prime.optimus

import com.esotericsoftware.kryo.io.Output
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertNotNull
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTimeoutPreemptively
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.io.ByteArrayInputStream
import java.io.ByteArrayOutputStream
import java.io.ObjectInputStream
import java.io.ObjectOutputStream
import java.lang.management.ManagementFactory
import java.math.BigInteger
import java.time.Duration
import kotlin.random.Random

/** Bytes from Redis are untrusted: every bad input must end in a CodecException, cheaply. */
internal class KryoCodecHostileBytesTest {

    private val codec = KryoCodec.builder().register(Pose::class.java).register(Route::class.java).build()

    private fun refused(bytes: ByteArray): CodecException =
        assertThrows(CodecException::class.java) { codec.decode(bytes) }

    /** The class tag Kryo writes for [sample]'s type, followed by [body]. */
    private fun craft(sample: Any, body: Output.() -> Unit): ByteArray {
        val tag = codec.encode(sample)[0]
        return Output(64, -1).apply { writeByte(tag); body() }.toBytes()
    }

    private val threads = ManagementFactory.getThreadMXBean() as com.sun.management.ThreadMXBean

    /** Decoding must fail with a CodecException and allocate less than 1 MB doing it. */
    private fun assertRefusedCheaply(bytes: ByteArray, what: String) {
        val id = Thread.currentThread().id
        val before = threads.getThreadAllocatedBytes(id)
        val e = assertThrows(CodecException::class.java, { codec.decode(bytes) }, what)
        val allocated = threads.getThreadAllocatedBytes(id) - before
        assertTrue(allocated < 1_000_000, "$what: decoding allocated $allocated bytes")
        assertTrue(e.message!!.contains("remain") || e.message!!.contains("negative"), "$what: ${e.message}")
    }

    @Test
    fun `huge length prefixes are refused before anything is allocated`() {
        val huge = Int.MAX_VALUE
        assertRefusedCheaply(craft(ByteArray(1)) { writeVarInt(huge, true) }, "byte[]")
        assertRefusedCheaply(craft(IntArray(1)) { writeVarInt(huge, true) }, "int[]")
        assertRefusedCheaply(craft(LongArray(1)) { writeVarInt(huge, true) }, "long[]")
        assertRefusedCheaply(craft(DoubleArray(1)) { writeVarInt(huge, true) }, "double[]")
        assertRefusedCheaply(craft(FloatArray(1)) { writeVarInt(huge, true) }, "float[]")
        assertRefusedCheaply(craft(ShortArray(1)) { writeVarInt(huge, true) }, "short[]")
        assertRefusedCheaply(craft(CharArray(1)) { writeVarInt(huge, true) }, "char[]")
        assertRefusedCheaply(craft(BooleanArray(1)) { writeVarInt(huge, true) }, "boolean[]")
        assertRefusedCheaply(craft("") { writeVarInt(huge, true) }, "String")
        assertRefusedCheaply(craft(BigInteger.ONE) { writeVarInt(huge, true) }, "BigInteger")
        assertRefusedCheaply(craft(listOf(1)) { writeVarInt(huge, true) }, "List")
        assertRefusedCheaply(craft(setOf(1)) { writeVarInt(huge, true) }, "Set")
        assertRefusedCheaply(craft(mapOf(1 to 1)) { writeVarInt(huge, true) }, "Map")
        assertRefusedCheaply(craft(listOf(1)) { writeVarInt(-5, true) }, "negative List size")
        // the same inside a registered record: name, then a String claiming 2^31 chars
        assertRefusedCheaply(
            craft(Route("", Pose(0.0, 0.0, 0.0), listOf(), mapOf(), null)) { writeVarInt(huge, true) },
            "String field",
        )
    }

    @Test
    fun `a class id this codec did not register is refused, naming the id`() {
        val e = refused(byteArrayOf(0x7F))
        assertTrue(e.message!!.contains("class id 125"), e.message)
        assertTrue(e.message!!.contains("fingerprint"), e.message)
    }

    @Test
    fun `a class named by its name is refused without loading it`() {
        val bytes = Output(64, -1).apply { writeVarInt(1, true); writeVarInt(0, true); writeString("java.util.HashMap") }.toBytes()
        val e = refused(bytes)
        assertTrue(e.message!!.contains("by its name"), e.message)
    }

    @Test
    fun `a Serializable class with a readObject side effect does not decode in a codec that did not register it`() {
        // The canary is live: Java serialization would trip it.
        Tripwire.TRIGGERED.set(false)
        val javaBytes = ByteArrayOutputStream().also { ObjectOutputStream(it).use { out -> out.writeObject(Tripwire("x")) } }.toByteArray()
        ObjectInputStream(ByteArrayInputStream(javaBytes)).use { it.readObject() }
        assertTrue(Tripwire.TRIGGERED.getAndSet(false))

        val writer = KryoCodec.builder().register(Tripwire::class.java).build()
        val bytes = writer.encode(Tripwire("boom"))
        val e = assertThrows(CodecException::class.java) { KryoCodec.standard().decode(bytes) }
        assertTrue(e.message!!.contains("which this codec does not know"), e.message)
        assertThrows(CodecException::class.java) { KryoCodec.standard().decode(javaBytes) }
        assertThrows(CodecException::class.java) { codec.decode(bytes) }
        assertFalse(Tripwire.TRIGGERED.get())
    }

    @Test
    fun `empty bytes, null, and trailing bytes are refused`() {
        refused(ByteArray(0))
        assertTrue(refused(byteArrayOf(0)).message!!.contains("null"))
        val good = codec.encode(Pose(1.0, 2.0, 3.0))
        assertTrue(refused(good + 0).message!!.contains("left over"))
    }

    @Test
    fun `every truncation of a valid encoding is refused`() {
        val route = Route("a route", Pose(1.0, 2.0, 3.0), listOf(Pose(4.0, 5.0, 6.0)), mapOf("k" to 1), "note ✓")
        val bytes = codec.encode(route)
        for (length in 1 until bytes.size) refused(bytes.copyOf(length))
        assertEquals(route, codec.decode(bytes))
    }

    @Test
    fun `bytes claiming deeper nesting than the limit are refused`() {
        val listTag = codec.encode(listOf<Any>())[0]
        val deep = Output(64, -1).apply {
            repeat(100_000) { writeByte(listTag); writeVarInt(1, true) }
            writeByte(0)
        }.toBytes()
        val e = refused(deep)
        assertTrue(e.message!!.contains("deeper than ${KryoCodec.DEFAULT_MAX_DEPTH}"), e.message)
    }

    @Test
    fun `random bytes either decode to a value or are refused with a CodecException`() {
        val random = Random(20261123)
        assertTimeoutPreemptively(Duration.ofSeconds(60)) {
            repeat(20_000) {
                val bytes = random.nextBytes(1 + random.nextInt(64))
                try {
                    assertNotNull(codec.decode(bytes))
                } catch (expected: CodecException) {
                    assertNotNull(expected.message)
                }
            }
        }
        // and it still works afterwards
        assertEquals(Pose(1.0, 2.0, 3.0), codec.decode(codec.encode(Pose(1.0, 2.0, 3.0))))
    }

    @Test
    fun `corrupting single bytes of a valid encoding never escapes as another exception`() {
        val route = Route("a route", Pose(1.0, 2.0, 3.0), listOf(Pose(4.0, 5.0, 6.0)), mapOf("k" to 1), null)
        val bytes = codec.encode(route)
        for (index in bytes.indices) {
            for (value in listOf(0, 1, 0x7F, 0x80, 0xFF)) {
                val corrupt = bytes.copyOf().also { it[index] = value.toByte() }
                try {
                    assertNotNull(codec.decode(corrupt))
                } catch (expected: CodecException) {
                    assertNotNull(expected.message)
                }
            }
        }
    }
}

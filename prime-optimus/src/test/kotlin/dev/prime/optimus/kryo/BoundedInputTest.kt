package dev.prime.optimus.kryo

import com.esotericsoftware.kryo.io.Output
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/** The length checks every serializer reads through, including Kryo's own String form. */
internal class BoundedInputTest {

    private fun input(body: Output.() -> Unit): BoundedInput =
        BoundedInput().apply { setBuffer(Output(64, -1).apply(body).toBytes()) }

    @Test
    fun `Kryo's string form still reads when its length fits`() {
        assertEquals("hello ✓ a string longer than thirty-two chars", input { writeString("hello ✓ a string longer than thirty-two chars") }.readString())
        assertEquals("short ascii", input { writeString("short ascii") }.readString())
    }

    @Test
    fun `Kryo's string form claiming more chars than bytes remain is refused`() {
        val e = assertThrows(RefusedBytesException::class.java) { input { writeVarIntFlag(true, Int.MAX_VALUE, true) }.readString() }
        assertTrue(e.message!!.contains("remain"), e.message)
        assertThrows(RefusedBytesException::class.java) { input { writeVarIntFlag(true, 1000, true); writeByte(65) }.readStringBuilder() }
    }

    @Test
    fun `bulk reads longer than the remaining bytes are refused, and fitting ones read`() {
        assertThrows(RefusedBytesException::class.java) { input { writeInt(1) }.readInts(2) }
        assertThrows(RefusedBytesException::class.java) { input { writeLong(1) }.readLongs(2) }
        assertThrows(RefusedBytesException::class.java) { input { writeByte(1) }.readBytes(2) }
        assertThrows(RefusedBytesException::class.java) { input { writeByte(1) }.readBytes(-1) }
        assertEquals(listOf(1, 2), input { writeInt(1); writeInt(2) }.readInts(2).toList())
    }
}

package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertArrayEquals
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Test

internal class HeldCodecSessionTest {

    private class Stranger

    private val codec = KryoCodec.standard()

    /** A codec whose pool holds one idle session: the one a plain encode used and gave back. */
    private fun warmed(): KryoCodec = codec.also {
        it.encode("warm-up")
        assertEquals(1, it.idleSessions())
    }

    @Test
    fun `a holder takes one session for many values and gives it back at close`() {
        val codec = warmed()
        val held = HeldCodecSession(codec)
        repeat(1000) { n ->
            val value = listOf(n, "value $n")
            val bytes = held.encode(value, 0)
            assertArrayEquals(codec.encode(value), bytes, "the held session writes what the codec writes")
            assertEquals(value, held.decode(bytes, 0, bytes.size))
            // the codec's own calls took the one idle session and gave it back; the holder still holds its own
            assertEquals(1, codec.idleSessions(), "idle sessions after value $n")
        }
        held.close()
        assertEquals(2, codec.idleSessions())
        held.close()
        assertEquals(2, codec.idleSessions(), "a second close gives nothing back")
    }

    @Test
    fun `room before the value and a value read in place`() {
        val held = HeldCodecSession(codec)
        val bytes = held.encode(42L, 3)
        assertEquals(listOf<Byte>(0, 0, 0), bytes.take(3))
        val framed = byteArrayOf(9, 9) + bytes.copyOfRange(3, bytes.size) + byteArrayOf(9)
        assertEquals(42L, held.decode(framed, 2, bytes.size - 3))
        held.close()
    }

    @Test
    fun `a failed encode drops the session it used, and the next value takes another`() {
        val codec = warmed()
        val held = HeldCodecSession(codec)
        held.encode("first", 0)
        assertEquals(0, codec.idleSessions())
        assertThrows(IllegalArgumentException::class.java) { held.encode(Stranger(), 0) }
        held.close()
        assertEquals(0, codec.idleSessions(), "the session the failure left in an unknown state is not given back")
        val bytes = held.encode("after", 0)
        assertEquals("after", held.decode(bytes, 0, bytes.size))
        held.close()
        assertEquals(1, codec.idleSessions())
    }

    @Test
    fun `a failed decode drops the session it used`() {
        val codec = warmed()
        val held = HeldCodecSession(codec)
        val bytes = held.encode("whole", 0)
        assertThrows(CodecException::class.java) { held.decode(bytes, 0, bytes.size - 2) }
        assertThrows(CodecException::class.java) { held.decode(bytes, 0, 0) }
        held.close()
        assertEquals(0, codec.idleSessions(), "the session the failure left in an unknown state is not given back")
        assertEquals("whole", held.decode(bytes, 0, bytes.size))
    }
}

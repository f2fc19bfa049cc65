package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertArrayEquals
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertSame
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.nio.ByteBuffer

/** The frame layout: packing splits by values and bytes, unpacking gives back every envelope, bad frames are refused. */
class FrameTest {

    private fun envelope(id: Long, size: Int) = Envelope.value(id, ByteArray(size) { (id + it).toByte() })

    @Test
    fun packingKeepsOrderAndSplitsByBytesAndValues() {
        val sizes = listOf(1, 100, 10_000, 70_000, 300, 0, 65_000)
        val envelopes = (0 until 700).map { envelope(it.toLong(), sizes[it % sizes.size]) }
        val frames = Frame.pack(envelopes, 64 * 1024, always = true)
        assertEquals(envelopes.map { it.toList() }, frames.flatMap(Frame::envelopes).map { it.toList() }, "every value, in order")
        for (frame in frames) {
            val count = Frame.count(frame)
            assertTrue(count <= Frame.MAX_VALUES, "$count values in a frame")
            assertTrue(frame.size <= 64 * 1024 || count == 1, "a frame of $count values has ${frame.size} bytes")
            assertEquals(count, Frame.queued(frame))
        }
        assertTrue(frames.size > 700 / Frame.MAX_VALUES, "split: ${frames.size} frames")
    }

    @Test
    fun aLoneEnvelopeStaysPlainUnlessAFrameIsRequired() {
        val one = envelope(1, 10)
        assertSame(one, Frame.pack(listOf(one), Frame.DEFAULT_BYTES, always = false).single())
        val framed = Frame.pack(listOf(one), Frame.DEFAULT_BYTES, always = true).single()
        assertTrue(Frame.isFrame(framed))
        assertArrayEquals(one, Frame.envelopes(framed).single())
        assertEquals(listOf(one.toList()), Frame.envelopes(one).map { it.toList() }, "a plain envelope is its own only value")
        assertEquals(0, Frame.queued(Envelope.request(2, "r".toByteArray(), null)), "a caller's request is not counted")
    }

    @Test
    fun badFramesAreRefusedWithAReason() {
        val frame = Frame.pack(listOf(envelope(1, 10), envelope(2, 10)), Frame.DEFAULT_BYTES, always = true).single()
        val future = frame.copyOf().also { it[1] = 2 }
        assertTrue("version 2" in assertThrows(CodecException::class.java) { Frame.envelopes(future) }.message!!)
        assertThrows(CodecException::class.java) { Frame.envelopes(frame.copyOf(frame.size - 3)) }
        assertThrows(CodecException::class.java) { Frame.envelopes(frame + byteArrayOf(0)) }
        val huge = frame.copyOf().also { ByteBuffer.wrap(it).putInt(10, Int.MAX_VALUE) }
        assertTrue("count" in assertThrows(CodecException::class.java) { Frame.envelopes(huge) }.message!!)
        assertThrows(CodecException::class.java) { Frame.envelopes(byteArrayOf(Frame.MAGIC, Frame.VERSION)) }
    }
}

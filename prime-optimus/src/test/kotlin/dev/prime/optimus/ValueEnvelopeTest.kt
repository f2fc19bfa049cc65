package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertArrayEquals
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test

/** A value's envelope encoded in place is the envelope built around the codec's bytes, with either codec. */
class ValueEnvelopeTest {

    /** A codec that is not a [KryoCodec]: its bytes are copied into an envelope. */
    private class Foreign : OptimusCodec by KryoCodec.standard()

    @Test
    fun anEnvelopeEncodedInPlaceHasTheBytesOfOneBuiltAroundTheEncoding() {
        for (codec in listOf(KryoCodec.standard(), Foreign())) {
            OptimusCore.builder().redis(TestRedis.url).codec(codec).build().use { core ->
                for (value in listOf<Any?>(7, "a text", ByteArray(100) { it.toByte() }, null)) {
                    val inPlace = Envelope.withId(core.valueEnvelope(value), 42L)
                    val built = Envelope.value(42L, core.encode(value))
                    assertArrayEquals(built, inPlace, "${codec.javaClass.simpleName}, $value")
                    val parsed = Envelope.parse(inPlace)
                    assertEquals(42L, parsed.id)
                    assertEquals(Envelope.Kind.VALUE, parsed.kind)
                }
            }
        }
    }
}

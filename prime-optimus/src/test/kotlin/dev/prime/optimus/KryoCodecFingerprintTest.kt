package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNotEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

internal class KryoCodecFingerprintTest {

    private fun codec(vararg types: Class<*>): KryoCodec =
        types.fold(KryoCodec.builder()) { builder, type -> builder.register(type) }.build()

    @Test
    fun `equal for the same registrations, in a short readable form`() {
        assertEquals(KryoCodec.standard().fingerprint(), KryoCodec.standard().fingerprint())
        assertEquals(codec(Pose::class.java, Route::class.java).fingerprint(), codec(Pose::class.java, Route::class.java).fingerprint())
        assertTrue(Regex("kryo-[0-9a-f]{16}").matches(KryoCodec.standard().fingerprint()), KryoCodec.standard().fingerprint())
    }

    @Test
    fun `different for other types or another order`() {
        val poseRoute = codec(Pose::class.java, Route::class.java).fingerprint()
        assertNotEquals(poseRoute, codec(Route::class.java, Pose::class.java).fingerprint())
        assertNotEquals(poseRoute, codec(Pose::class.java).fingerprint())
        assertNotEquals(poseRoute, KryoCodec.standard().fingerprint())
        assertNotEquals(KryoCodec.standard().fingerprint(), codec(Pose::class.java).fingerprint())
    }

    @Test
    fun `registered types are listed by id, built-ins first and the application's in registration order`() {
        val types = codec(Route::class.java, Pose::class.java).registeredTypes()
        assertEquals("1 java.lang.String", types[1])
        assertTrue(types.contains("10 [B"), types.toString())
        assertTrue(types.contains("20 java.util.List"), types.toString())
        assertTrue(types.any { it.endsWith(" dev.prime.Token") }, types.toString())
        assertEquals(listOf("100 ${Route::class.java.name}", "101 ${Pose::class.java.name}"), types.takeLast(2))
    }

    @Test
    fun `the same value is read as another type when the order differs, which is why fingerprints must match`() {
        val writer = codec(Pose::class.java, Label::class.java)
        val reader = codec(Label::class.java, Pose::class.java)
        assertNotEquals(writer.fingerprint(), reader.fingerprint())
        // Pose is id 100 for the writer but Label for the reader: the bytes do not make sense to it.
        assertThrows(CodecException::class.java) { reader.decode(writer.encode(Pose(1.0, 2.0, 3.0))) }
    }
}

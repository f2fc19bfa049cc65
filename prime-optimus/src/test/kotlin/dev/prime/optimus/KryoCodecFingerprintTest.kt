package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertArrayEquals
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNotEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

internal class KryoCodecFingerprintTest {

    private fun codec(vararg types: Class<*>): KryoCodec =
        types.fold(KryoCodec.builder()) { builder, type -> builder.allow(type) }.build()

    @Test
    fun `equal for the same allowed types in any order, in a short readable form`() {
        assertEquals(KryoCodec.standard().fingerprint(), KryoCodec.standard().fingerprint())
        assertEquals(codec(Pose::class.java, Route::class.java).fingerprint(), codec(Pose::class.java, Route::class.java).fingerprint())
        assertEquals(codec(Pose::class.java, Route::class.java).fingerprint(), codec(Route::class.java, Pose::class.java).fingerprint())
        assertTrue(Regex("kryo-[0-9a-f]{16}").matches(KryoCodec.standard().fingerprint()), KryoCodec.standard().fingerprint())
    }

    @Test
    fun `different for other types`() {
        val poseRoute = codec(Pose::class.java, Route::class.java).fingerprint()
        assertNotEquals(poseRoute, codec(Pose::class.java).fingerprint())
        assertNotEquals(poseRoute, codec(Pose::class.java, Label::class.java).fingerprint())
        assertNotEquals(poseRoute, KryoCodec.standard().fingerprint())
        assertNotEquals(KryoCodec.standard().fingerprint(), codec(Pose::class.java).fingerprint())
    }

    @Test
    fun `registered types are listed by id, built-ins first, then the declared types by name, then the rules`() {
        val types = codec(Route::class.java, Pose::class.java).registeredTypes()
        assertEquals("1 java.lang.String", types[1])
        assertTrue(types.contains("10 [B"), types.toString())
        assertTrue(types.contains("20 java.util.List"), types.toString())
        assertTrue(types.any { it.endsWith(" dev.prime.Token") }, types.toString())
        assertEquals(listOf("100 ${Pose::class.java.name}", "101 ${Route::class.java.name}", "records and enums sent"), types.takeLast(3))
    }

    @Test
    fun `a declared record keeps its short id when records are also learned`() {
        val declared = codec(Pose::class.java)
        val bytes = declared.encode(Pose(1.0, 2.0, 3.0))
        assertEquals(102, bytes[0].toInt(), "id 100, one byte on the wire")
        assertArrayEquals(bytes, codec(Pose::class.java).encode(Pose(1.0, 2.0, 3.0)))
        val learned = KryoCodec.standard().encode(Pose(1.0, 2.0, 3.0))
        assertEquals(bytes.size + 3, learned.size, "a learned record is sent under a four-byte hash id")
    }
}

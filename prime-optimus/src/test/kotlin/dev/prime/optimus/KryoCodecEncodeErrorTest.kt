package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

internal class KryoCodecEncodeErrorTest {

    private val codec = KryoCodec.builder().register(Pose::class.java).register(Parcel::class.java).build()

    private fun assertUnregistered(value: Any, missing: Class<*>) {
        val e = assertThrows(IllegalArgumentException::class.java) { codec.encode(value) }
        val what = if (value.javaClass == missing) "the type is not allowed" else "it contains a ${missing.name}, which is not allowed"
        assertEquals(
            "KryoCodec cannot encode a value of type ${value.javaClass.name}: $what (records and enums are accepted " +
                "without configuration; Stranger is neither). Allow it where the codec is built: " +
                "KryoCodec.builder().allow(Stranger.class) (Kotlin: allow(Stranger::class.java)), or allow its whole " +
                "package: KryoCodec.builder().allowPackage(\"dev.prime.optimus\"). Every process of the topology must " +
                "allow the same types",
            e.message,
        )
    }

    @Test
    fun `a nested class is named as in source, and a strict codec does not mention records`() {
        val e = assertThrows(IllegalArgumentException::class.java) {
            KryoCodec.builder().learnRecordsAndEnums(false).build().encode(Outer.Inner(1))
        }
        assertEquals(
            "KryoCodec cannot encode a value of type dev.prime.optimus.KryoCodecEncodeErrorTest\$Outer\$Inner: the type " +
                "is not allowed. Allow it where the codec is built: " +
                "KryoCodec.builder().allow(KryoCodecEncodeErrorTest.Outer.Inner.class) (Kotlin: " +
                "allow(KryoCodecEncodeErrorTest.Outer.Inner::class.java)), or allow its whole package: " +
                "KryoCodec.builder().allowPackage(\"dev.prime.optimus\"). Every process of the topology must allow " +
                "the same types",
            e.message,
        )
    }

    internal class Outer {
        @JvmRecord
        internal data class Inner(val x: Int)
    }

    @Test
    fun `an unregistered type is refused with a message naming it and how to register it`() {
        assertUnregistered(Stranger("s"), Stranger::class.java)
    }

    @Test
    fun `an unregistered element inside a built-in container is refused the same way`() {
        assertUnregistered(listOf(1, Stranger("s")), Stranger::class.java)
        assertUnregistered(mapOf("k" to Stranger("s")), Stranger::class.java)
        assertUnregistered(java.util.Optional.of(Stranger("s")), Stranger::class.java)
        assertUnregistered(dev.prime.Tuple2(1, Stranger("s")), Stranger::class.java)
    }

    @Test
    fun `an unregistered value inside a registered record is refused the same way`() {
        assertUnregistered(Parcel(1, Stranger("s")), Stranger::class.java)
        assertUnregistered(Parcel(1, listOf(Parcel(2, Stranger("s")))), Stranger::class.java)
    }

    @Test
    fun `the codec stays usable after a refused value`() {
        repeat(3) { assertThrows(IllegalArgumentException::class.java) { codec.encode(Stranger("s")) } }
        assertEquals(Pose(1.0, 2.0, 3.0), codec.decode(codec.encode(Pose(1.0, 2.0, 3.0))))
    }

    @Test
    fun `a value nested deeper than the limit is refused, and so is a cycle`() {
        val shallow = KryoCodec.builder().maxDepth(8).build()
        var nested: Any = 1
        repeat(20) { nested = listOf(nested) }
        val e = assertThrows(IllegalArgumentException::class.java) { shallow.encode(nested) }
        assertTrue(e.message!!.contains("deeper than 8"), e.message)

        val cycle = ArrayList<Any>()
        cycle.add(cycle)
        assertThrows(IllegalArgumentException::class.java) { codec.encode(cycle) }
    }

    @Test
    fun `registering a built-in, a duplicate, an interface, an array or a collection is refused`() {
        val builder = KryoCodec.builder().register(Pose::class.java)
        for (bad in listOf(
            String::class.java, Int::class.javaObjectType, Int::class.javaPrimitiveType!!, ByteArray::class.java,
            ArrayList::class.java, java.util.HashMap::class.java, dev.prime.Token::class.java, dev.prime.Tuple2::class.java,
            Pose::class.java, Shape::class.java, AbstractShape::class.java, Array<Pose>::class.java,
            java.util.ArrayDeque::class.java,
        )) {
            val e = assertThrows(IllegalArgumentException::class.java, { builder.register(bad) }, bad.name)
            assertTrue(e.message!!.contains(bad.name) || e.message!!.contains(bad.typeName), e.message)
        }
    }

    @Test
    fun `a type that asks for Java serialization is refused when the codec is built`() {
        val builder = KryoCodec.builder().register(AsksForJavaSerialization::class.java)
        val e = assertThrows(IllegalArgumentException::class.java) { builder.build() }
        assertTrue(e.message!!.contains("Java serialization"), e.message)
    }

    @Test
    fun `maxDepth must be positive`() {
        assertThrows(IllegalArgumentException::class.java) { KryoCodec.builder().maxDepth(0) }
    }
}

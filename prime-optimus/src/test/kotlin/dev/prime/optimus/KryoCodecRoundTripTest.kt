package dev.prime.optimus

import dev.prime.Repeat
import dev.prime.Tick
import dev.prime.Token
import dev.prime.Tuple2
import dev.prime.Tuple3
import dev.prime.Tuple4
import dev.prime.Tuple5
import org.junit.jupiter.api.Assertions.assertArrayEquals
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertInstanceOf
import org.junit.jupiter.api.Assertions.assertSame
import org.junit.jupiter.api.Test
import org.junit.jupiter.params.ParameterizedTest
import org.junit.jupiter.params.provider.MethodSource
import java.math.BigDecimal
import java.math.BigInteger
import java.time.Duration
import java.time.Instant
import java.time.LocalDate
import java.time.LocalDateTime
import java.time.LocalTime
import java.util.Arrays
import java.util.Collections
import java.util.LinkedList
import java.util.Optional
import java.util.TreeMap
import java.util.UUID

internal class KryoCodecRoundTripTest {

    private val standard = KryoCodec.standard()
    private val app = KryoCodec.builder()
        .register(Pose::class.java)
        .register(Route::class.java)
        .register(Parcel::class.java)
        .register(Packet::class.java)
        .register(Counter::class.java)
        .register(Label::class.java)
        .register(Colour::class.java)
        .register(Tripwire::class.java)
        .build()

    private fun roundTrip(codec: OptimusCodec, value: Any): Any = codec.decode(codec.encode(value))

    @ParameterizedTest
    @MethodSource("builtInValues")
    fun `every built-in value round-trips to an equal value of the same class`(value: Any) {
        val back = roundTrip(standard, value)
        assertEquals(value, back)
        assertEquals(value.javaClass, back.javaClass)
    }

    @Test
    fun `primitive arrays round-trip with their content`() {
        assertArrayEquals(byteArrayOf(0, -1, 127, -128), roundTrip(standard, byteArrayOf(0, -1, 127, -128)) as ByteArray)
        assertArrayEquals(shortArrayOf(1, -2, Short.MAX_VALUE), roundTrip(standard, shortArrayOf(1, -2, Short.MAX_VALUE)) as ShortArray)
        assertArrayEquals(intArrayOf(1, -2, Int.MIN_VALUE), roundTrip(standard, intArrayOf(1, -2, Int.MIN_VALUE)) as IntArray)
        assertArrayEquals(longArrayOf(1, -2, Long.MAX_VALUE), roundTrip(standard, longArrayOf(1, -2, Long.MAX_VALUE)) as LongArray)
        assertArrayEquals(floatArrayOf(1.5f, Float.NaN), roundTrip(standard, floatArrayOf(1.5f, Float.NaN)) as FloatArray)
        assertArrayEquals(doubleArrayOf(-0.0, Double.MIN_VALUE), roundTrip(standard, doubleArrayOf(-0.0, Double.MIN_VALUE)) as DoubleArray)
        assertArrayEquals(charArrayOf('a', 'ü', '\u0000'), roundTrip(standard, charArrayOf('a', 'ü', '\u0000')) as CharArray)
        assertArrayEquals(booleanArrayOf(true, false, true), roundTrip(standard, booleanArrayOf(true, false, true)) as BooleanArray)
        assertArrayEquals(ByteArray(0), roundTrip(standard, ByteArray(0)) as ByteArray)
        assertArrayEquals(ByteArray(100_000) { it.toByte() }, roundTrip(standard, ByteArray(100_000) { it.toByte() }) as ByteArray)
    }

    @ParameterizedTest
    @MethodSource("lists")
    fun `any List reads back as an equal ArrayList`(list: List<*>) {
        val back = roundTrip(standard, list)
        assertInstanceOf(ArrayList::class.java, back)
        assertEquals(list, back)
    }

    @ParameterizedTest
    @MethodSource("maps")
    fun `any Map reads back as an equal LinkedHashMap in the same order`(map: Map<*, *>) {
        val back = roundTrip(standard, map)
        assertInstanceOf(LinkedHashMap::class.java, back)
        assertEquals(map, back)
        assertEquals(map.keys.toList(), (back as Map<*, *>).keys.toList())
    }

    @Test
    fun `any Set reads back as an equal LinkedHashSet`() {
        for (set in listOf(setOf(1, 2, 3), java.util.Set.of("a", "b"), HashSet(listOf(4, 5)), emptySet<Any>(), sortedSetOf(3, 1, 2))) {
            val back = roundTrip(standard, set)
            assertInstanceOf(LinkedHashSet::class.java, back)
            assertEquals(set, back)
        }
    }

    @Test
    fun `a String is written as its class id, its UTF-8 length and its UTF-8 bytes`() {
        val bytes = standard.encode("aé")
        assertEquals(listOf(3, 3, 'a'.code, 0xC3, 0xA9), bytes.map { it.toInt() and 0xFF })
    }

    @Test
    fun `Token decodes as the one instance`() {
        assertSame(Token.INSTANCE, roundTrip(standard, Token.INSTANCE))
        assertSame(Token.INSTANCE, (roundTrip(standard, listOf(Token.INSTANCE)) as List<*>)[0])
    }

    @Test
    fun `Tick is built in - a codec that learns nothing reads one it never sent`() {
        fun strict() = KryoCodec.builder().learnRecordsAndEnums(false).build()
        val tick = Tick(3, Instant.parse("2026-11-27T06:00:00.5Z"))
        assertEquals(tick, strict().decode(strict().encode(tick)))
    }

    @Test
    fun `tuples and Repeat carry nested values`() {
        val tuple = Tuple3(Tuple2(1, "a"), listOf(1L, 2L), Repeat.stop<String, Any>(mapOf("k" to 1.5)))
        assertEquals(tuple, roundTrip(standard, tuple))
        val again = Repeat.again<Any, String>(Tuple2(Token.INSTANCE, null))
        assertEquals(again, roundTrip(standard, again))
    }

    @Test
    fun `a record with a nested record, a List and a Map field round-trips`() {
        val route = Route(
            name = "dock → gate",
            start = Pose(0.0, 0.0, 1.57),
            waypoints = listOf(Pose(1.0, 2.0, 0.0), Pose(3.5, -4.25, 3.14)),
            speeds = linkedMapOf("fast" to 3, "slow" to 1),
            note = null,
        )
        assertEquals(route, roundTrip(app, route))
        assertEquals(listOf(route, route), roundTrip(app, listOf(route, route)))
    }

    @Test
    fun `records, POJOs, data classes and enums the application registered round-trip`() {
        assertEquals(Packet(7, byteArrayOf(1, 2, 3)), roundTrip(app, Packet(7, byteArrayOf(1, 2, 3))))
        assertEquals(Counter("laps", 42, listOf(1, 2, 3)), roundTrip(app, Counter("laps", 42, listOf(1, 2, 3))))
        assertEquals(Label("hello", -3), roundTrip(app, Label("hello", -3)))
        assertSame(Colour.BLUE, roundTrip(app, Colour.BLUE))
        assertEquals(Parcel(1, Tuple2(Pose(1.0, 1.0, 1.0), Colour.RED)), roundTrip(app, Parcel(1, Tuple2(Pose(1.0, 1.0, 1.0), Colour.RED))))
        assertEquals(Parcel(2, null), roundTrip(app, Parcel(2, null)))
    }

    @Test
    fun `a registered Serializable class is written field by field, without running readObject`() {
        Tripwire.TRIGGERED.set(false)
        assertEquals(Tripwire("x"), roundTrip(app, Tripwire("x")))
        assertEquals(false, Tripwire.TRIGGERED.get())
    }

    @Test
    fun `codecs built alike read each other's bytes`() {
        val other = KryoCodec.builder()
            .register(Pose::class.java).register(Route::class.java).register(Parcel::class.java)
            .register(Packet::class.java).register(Counter::class.java).register(Label::class.java)
            .register(Colour::class.java).register(Tripwire::class.java)
            .build()
        val route = Route("r", Pose(1.0, 2.0, 3.0), listOf(), mapOf(), "n")
        assertEquals(route, other.decode(app.encode(route)))
    }

    companion object {
        @JvmStatic
        fun builtInValues(): List<Any> = listOf(
            42, -1, Int.MAX_VALUE, 7L, Long.MIN_VALUE, 3.toShort(), (-8).toByte(), 2.5f, Math.PI,
            Double.NaN, true, false, 'x', 'é',
            "", "a", "plain ascii", "ascii longer than thirty-two characters, many of them",
            "ünïcödé ✓ 𝄞", "x".repeat(100_000),
            BigInteger("123456789012345678901234567890"), BigInteger.ZERO, BigInteger("-1"),
            BigDecimal("-12345.678900"), BigDecimal.ZERO,
            Optional.of("present"), Optional.empty<Any>(),
            UUID.fromString("123e4567-e89b-12d3-a456-426614174000"),
            Instant.parse("2026-11-23T01:30:00.123456789Z"), Duration.ofMillis(1500),
            LocalDate.of(2026, 11, 23), LocalTime.of(1, 30), LocalDateTime.of(2026, 11, 23, 1, 30),
            Tuple2("a", 1), Tuple3(1, 2, 3), Tuple4(1, "b", 2.0, null), Tuple5(1, 2, 3, 4, listOf(5)),
            Repeat.again<Int, Int>(3), Repeat.stop<Int, String>("done"),
            arrayListOf(1, "two", 3.0),
        )

        @JvmStatic
        fun lists(): List<List<*>> = listOf(
            java.util.List.of(1, 2, 3),
            java.util.List.of<Any>(),
            java.util.List.of("only"),
            Arrays.asList("a", null, "c"),
            Collections.unmodifiableList(arrayListOf(1, 2)),
            Collections.singletonList(Token.INSTANCE),
            Collections.emptyList<Any>(),
            LinkedList(listOf(1L, 2L)),
            listOf(listOf(1, 2), listOf(3), emptyList<Int>()),
            (1..10).toList(),
            arrayListOf(mapOf("k" to listOf(1)), setOf(2)),
        )

        @JvmStatic
        fun maps(): List<Map<*, *>> = listOf(
            hashMapOf("a" to 1, "b" to 2),
            linkedMapOf(3 to "c", 1 to "a", 2 to "b"),
            java.util.Map.of("k", listOf(1, 2)),
            TreeMap(mapOf("z" to 1, "a" to 2)),
            Collections.unmodifiableMap(mapOf(1 to null)),
            emptyMap<Any, Any>(),
            Collections.singletonMap(Token.INSTANCE, Tuple2(1, 2)),
        )
    }
}

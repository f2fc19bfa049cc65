package dev.prime.optimus.kryo

import com.esotericsoftware.kryo.Kryo
import com.esotericsoftware.kryo.Registration
import com.esotericsoftware.kryo.Serializer
import com.esotericsoftware.kryo.serializers.DefaultArraySerializers
import com.esotericsoftware.kryo.serializers.DefaultSerializers
import com.esotericsoftware.kryo.serializers.ExternalizableSerializer
import com.esotericsoftware.kryo.serializers.OptionalSerializers
import com.esotericsoftware.kryo.serializers.RecordSerializer
import com.esotericsoftware.kryo.serializers.TimeSerializers
import com.esotericsoftware.kryo.serializers.JavaSerializer
import com.esotericsoftware.kryo.util.DefaultInstantiatorStrategy
import dev.prime.Repeat
import dev.prime.Tick
import dev.prime.Token
import dev.prime.Tuple2
import dev.prime.Tuple3
import dev.prime.Tuple4
import dev.prime.Tuple5
import org.objenesis.strategy.StdInstantiatorStrategy
import java.math.BigDecimal
import java.math.BigInteger
import java.security.MessageDigest
import java.time.Duration
import java.time.Instant
import java.time.LocalDate
import java.time.LocalDateTime
import java.time.LocalTime
import java.util.Optional
import java.util.UUID

/**
 * The registration table of one codec, and the factory of its [Kryo] instances.
 *
 * Ids are fixed so that every process that allows the same application types assigns the same
 * ids, whatever the order they were declared or first seen in:
 * - 0..8: Kryo's own (`int`, `String`, `float`, `boolean`, `byte`, `char`, `short`, `long`,
 *   `double`; each boxed type shares its primitive's registration);
 * - [FIRST_BUILT_IN_ID]..: [BUILT_INS], in list order;
 * - [AllowList.FIRST_USER_ID]..: the declared application types, sorted by class name (a gap
 *   above the built-ins, so adding a built-in later does not move the application's ids);
 * - [AllowList.FIRST_HASH_ID]..: types admitted lazily (a class of an allowed package, a
 *   record or enum this process sends), each under a hash of its name (see [AllowList]).
 *
 * Immutable and thread-safe; [newKryo] builds a fresh, unshared Kryo each time.
 */
internal class KryoRegistry(val allowList: AllowList, val maxDepth: Int) {

    /**
     * `"id class-name"` for every registration made when the codec is built, ordered by id, then
     * the rules that admit types lazily (`"package com.acme"`, `"records and enums sent"`).
     */
    val typeNames: List<String>

    /** A short hash of [typeNames] and the wire-format version. */
    val fingerprint: String

    init {
        val kryo = newKryo()
        typeNames = (0 until AllowList.FIRST_USER_ID + allowList.declared.size).mapNotNull { id ->
            kryo.classResolver.getRegistration(id)?.let { "$id ${it.type.name}" }
        } + allowList.rules
        val digest = MessageDigest.getInstance("SHA-256")
            .digest((listOf(FORMAT) + typeNames).joinToString("\n").toByteArray(Charsets.UTF_8))
        fingerprint = "kryo-" + digest.take(FINGERPRINT_BYTES).joinToString("") { "%02x".format(it) }
    }

    /**
     * A new Kryo with registration required, no references, the [maxDepth] limit, and every
     * registration of this table.
     *
     * @throws IllegalArgumentException if an application type cannot be registered safely
     */
    fun newKryo(): Kryo {
        val kryo = AllowListKryo(AllowListClassResolver(allowList, knownIds()))
        kryo.isRegistrationRequired = true
        kryo.warnUnregisteredClasses = false
        kryo.references = false
        kryo.setMaxDepth(maxDepth)
        // No-arg constructor when there is one, else create without calling a constructor (as
        // for Kotlin data classes); the fields are then set from the bytes.
        kryo.instantiatorStrategy = DefaultInstantiatorStrategy(StdInstantiatorStrategy())
        // Kryo registers String as id 1 with a char-by-char serializer; ours is faster. Strings
        // Kryo writes on its own (none with the default field serializers) still read through
        // BoundedInput.readString's length check.
        kryo.register(String::class.java, Utf8StringSerializer(), STRING_ID)
        BUILT_INS.forEachIndexed { index, (type, serializer) ->
            val id = FIRST_BUILT_IN_ID + index
            kryo.register(type, serializer(), id)
        }
        allowList.declared.forEach { (id, type) ->
            val registration = try {
                kryo.register(type, id)
            } catch (e: RuntimeException) {
                throw IllegalArgumentException(
                    "KryoCodec cannot register ${type.name}: ${e.message}. Allow records or " +
                        "classes whose fields Kryo can read and write",
                    e,
                )
            }
            refuseJavaSerialization(registration)
        }
        return kryo
    }

    private fun knownIds(): String {
        val lastBuiltIn = FIRST_BUILT_IN_ID + BUILT_INS.size - 1
        val declared = allowList.declared.size
        val user = if (declared == 0) "no declared application types" else
            "declared application types ${AllowList.FIRST_USER_ID}-${AllowList.FIRST_USER_ID + declared - 1}"
        val lazily = if (allowList.rules.isEmpty()) "" else ", and by name hash: " + allowList.rules.joinToString()
        return "0-8 (Kryo's), $FIRST_BUILT_IN_ID-$lastBuiltIn (built in), $user$lazily"
    }

    companion object {
        /**
         * Refuses a registration whose serializer is Java serialization (a type annotated
         * `@DefaultSerializer(JavaSerializer::class)` or the like).
         *
         * @throws IllegalArgumentException naming the type and what to change
         */
        fun refuseJavaSerialization(registration: Registration) {
            val serializer = registration.serializer
            require(serializer !is JavaSerializer && serializer !is ExternalizableSerializer) {
                "KryoCodec does not allow ${registration.type.name}: it asks for " +
                    "${serializer.javaClass.simpleName} (Java serialization), which the codec " +
                    "never runs on bytes from Redis. Remove its @DefaultSerializer annotation"
            }
        }

        /** Wire-format version of this codec's own serializers; part of the fingerprint. */
        private const val FORMAT = "optimus-kryo5-v3"
        private const val FINGERPRINT_BYTES = 8
        const val FIRST_BUILT_IN_ID = 10
        private const val STRING_ID = 1

        /** Built-in types in id order, each with the factory of its (stateless) serializer. */
        private val BUILT_INS: List<Pair<Class<*>, () -> Serializer<*>>> = listOf(
            ByteArray::class.java to { DefaultArraySerializers.ByteArraySerializer() },
            ShortArray::class.java to { DefaultArraySerializers.ShortArraySerializer() },
            IntArray::class.java to { DefaultArraySerializers.IntArraySerializer() },
            LongArray::class.java to { DefaultArraySerializers.LongArraySerializer() },
            FloatArray::class.java to { DefaultArraySerializers.FloatArraySerializer() },
            DoubleArray::class.java to { DefaultArraySerializers.DoubleArraySerializer() },
            CharArray::class.java to { DefaultArraySerializers.CharArraySerializer() },
            BooleanArray::class.java to { BooleanArraySerializer() },
            BigInteger::class.java to { DefaultSerializers.BigIntegerSerializer() },
            BigDecimal::class.java to { DefaultSerializers.BigDecimalSerializer() },
            List::class.java to { CollectionSerializer.ofLists() },
            Set::class.java to { CollectionSerializer.ofSets() },
            Map::class.java to { MapSerializer() },
            Optional::class.java to { OptionalSerializers.OptionalSerializer() },
            UUID::class.java to { DefaultSerializers.UUIDSerializer() },
            Instant::class.java to { TimeSerializers.InstantSerializer() },
            Duration::class.java to { TimeSerializers.DurationSerializer() },
            LocalDate::class.java to { TimeSerializers.LocalDateSerializer() },
            LocalTime::class.java to { TimeSerializers.LocalTimeSerializer() },
            LocalDateTime::class.java to { TimeSerializers.LocalDateTimeSerializer() },
            Token::class.java to { DefaultSerializers.EnumSerializer(Token::class.java) },
            Tuple2::class.java to { RecordSerializer(Tuple2::class.java) },
            Tuple3::class.java to { RecordSerializer(Tuple3::class.java) },
            Tuple4::class.java to { RecordSerializer(Tuple4::class.java) },
            Tuple5::class.java to { RecordSerializer(Tuple5::class.java) },
            Repeat::class.java to { RepeatSerializer() },
            Tick::class.java to { RecordSerializer(Tick::class.java) },
        )

        private val KRYO_DEFAULTS: Set<Class<*>> = setOf(
            Int::class.javaPrimitiveType!!, Int::class.javaObjectType,
            String::class.java,
            Float::class.javaPrimitiveType!!, Float::class.javaObjectType,
            Boolean::class.javaPrimitiveType!!, Boolean::class.javaObjectType,
            Byte::class.javaPrimitiveType!!, Byte::class.javaObjectType,
            Char::class.javaPrimitiveType!!, Char::class.javaObjectType,
            Short::class.javaPrimitiveType!!, Short::class.javaObjectType,
            Long::class.javaPrimitiveType!!, Long::class.javaObjectType,
            Double::class.javaPrimitiveType!!, Double::class.javaObjectType,
        )

        /** Whether [type] is covered without registration (so registering it is a mistake). */
        fun isBuiltIn(type: Class<*>): Boolean =
            type in KRYO_DEFAULTS ||
                BUILT_INS.any { it.first == type } ||
                List::class.java.isAssignableFrom(type) ||
                Set::class.java.isAssignableFrom(type) ||
                Map::class.java.isAssignableFrom(type)
    }
}

package dev.prime.optimus

import com.esotericsoftware.kryo.KryoException
import dev.prime.optimus.kryo.KryoRegistry
import dev.prime.optimus.kryo.KryoSessionPool
import dev.prime.optimus.kryo.RefusedBytesException
import dev.prime.optimus.kryo.UnregisteredTypeException

/**
 * The default [OptimusCodec]: Kryo 5 with registration required.
 *
 * Only registered types are written or read. Built in, in a fixed order: primitives and their
 * boxes, `String`, the primitive arrays, `BigInteger`, `BigDecimal`, any `java.util.List`,
 * `Set` and `Map` (read back as `ArrayList`, `LinkedHashSet`, `LinkedHashMap`: equal to what was
 * written, though not of the same class), `Optional`, `UUID`, `Instant`, `Duration`,
 * `LocalDate`, `LocalTime`, `LocalDateTime`, and Prime's [dev.prime.Token] (decoded as
 * `Token.INSTANCE`), [dev.prime.Tuple2]..[dev.prime.Tuple5], [dev.prime.Repeat] and [dev.prime.Tick]. The
 * application registers its own records and classes with [builder]; every process that shares a
 * topology must register the same types in the same order, which [fingerprint] lets them check.
 *
 * ```java
 * OptimusCodec codec = KryoCodec.builder().register(Pose.class).register(Order.class).build();
 * ```
 *
 * ## Design note
 * - **Why Kryo.** Fast and compact: class ids instead of names, variable-length integers, records
 *   through their canonical constructor, buffers reused from a pool. Measured (`CodecBenchmark`
 *   in prime-bench, README "Codec cost"; 2-vCPU EPYC, JDK 17): a 100 B record encodes and
 *   decodes in about 0.2 µs each, a 10 KB one in 1.3-2.3 µs and 1-1.4 µs, allocating the result
 *   plus about 230 B. Well kept: 5.6.2 is
 *   from 2024, the project has been maintained for over a decade and is used by Flink, Spark and
 *   Storm; its dependencies are small (Objenesis, ReflectASM, MinLog). Registration-required is
 *   its default in version 5, so the safe mode is the ordinary mode, not a bolt-on.
 *   Considered:
 *   - Jackson with a polymorphic type validator: safe when configured right, but every value
 *     needs its type in the JSON (`@JsonTypeInfo` or default typing), safety rests on that
 *     validator being set up everywhere, and JSON is larger (text numbers, base64 for `byte[]`)
 *     and slower to write and parse;
 *   - Java serialization: never; it runs code chosen by the bytes;
 *   - Protocol Buffers: fast and safe, but needs a schema and generated classes for every value
 *     type, while Prime sends plain records;
 *   - Apache Fury: fast, but young, and its safety also comes down to class registration.
 * - **Safety.** Kryo reads only registered class ids; its "class by name" form is refused, so
 *   bytes can never make the process load or create a class the application did not allow.
 *   Java serialization is never used (a type whose `@DefaultSerializer` asks for it is refused
 *   at registration). Every length prefix is checked against the bytes that remain before
 *   anything is allocated, nesting is limited ([Builder.maxDepth]), and any failure while
 *   reading becomes a [CodecException].
 * - **Threading.** Kryo instances are not thread-safe. Each call takes a Kryo with its buffers
 *   from a thread-safe pool and gives it back; a call that failed drops its Kryo instead, so no
 *   half-updated state is reused. Idle instances kept: at most 4 per processor (≥ 8).
 * - **Memory.** Per pooled instance: Kryo's tables (a few KB) and an output buffer that grows to
 *   the largest value written, shrunk back after values over 64 KB. `encode` returns a copy of
 *   exactly the written bytes.
 */
public class KryoCodec private constructor(private val registry: KryoRegistry) : OptimusCodec {

    private val sessions = KryoSessionPool(registry, maxOf(MIN_POOLED, 4 * Runtime.getRuntime().availableProcessors()))

    /**
     * Encodes [value] with its class id.
     *
     * @throws IllegalArgumentException if the value, or anything inside it, has a type this codec
     *   has not registered (the message says how to register it), nests deeper than the limit, or
     *   cannot be written for another reason
     */
    override fun encode(value: Any): ByteArray {
        val session = sessions.obtain()
        val bytes = try {
            session.encode(value)
        } catch (e: RuntimeException) {
            throw encodeFailure(value, e)
        } catch (e: StackOverflowError) {
            throw encodeFailure(value, e)
        }
        sessions.free(session)
        return bytes
    }

    /**
     * Decodes bytes written by an agreeing codec (same [fingerprint]).
     *
     * @throws CodecException if the bytes are empty, truncated, malformed, have bytes left over,
     *   hold `null`, or name a class this codec has not registered
     */
    override fun decode(bytes: ByteArray): Any {
        if (bytes.isEmpty()) throw CodecException("KryoCodec cannot decode 0 bytes: there is no value")
        val session = sessions.obtain()
        val value = try {
            session.decode(bytes)
        } catch (e: RuntimeException) {
            throw decodeFailure(bytes, e)
        } catch (e: StackOverflowError) {
            throw decodeFailure(bytes, e)
        }
        sessions.free(session)
        return value ?: throw CodecException(
            "KryoCodec cannot decode ${bytes.size} bytes: they hold null, which the core never encodes",
        )
    }

    /**
     * `"kryo-"` and 16 hex digits: a hash of every registered class name with its id, and of the
     * wire-format version. Equal for codecs that read each other's bytes.
     */
    override fun fingerprint(): String = registry.fingerprint

    /** Every registration as `"id class-name"`, ordered by id: what [fingerprint] hashes. */
    public fun registeredTypes(): List<String> = registry.typeNames

    override fun toString(): String = "KryoCodec(${fingerprint()})"

    private fun encodeFailure(value: Any, e: Throwable): IllegalArgumentException {
        val unregistered = e.causes().filterIsInstance<UnregisteredTypeException>().firstOrNull()
        val type = value.javaClass.name
        if (unregistered != null) {
            val missing = unregistered.type
            val where = if (missing == value.javaClass) "" else ": it contains a ${missing.name}, which"
            val sourceName = missing.canonicalName ?: missing.name
            return IllegalArgumentException(
                "KryoCodec cannot encode a value of type $type$where is not registered. Register " +
                    "it when building the codec: KryoCodec.builder().register($sourceName.class)" +
                    " (Kotlin: register(${missing.simpleName}::class.java)); every process of the " +
                    "topology must register the same types in the same order",
                e,
            )
        }
        val reason = when {
            e is StackOverflowError -> "it nests too deeply"
            e.exceedsDepth() -> "it nests deeper than ${registry.maxDepth} levels (or contains a cycle)"
            else -> e.message ?: e.toString()
        }
        return IllegalArgumentException("KryoCodec cannot encode a value of type $type: $reason", e)
    }

    private fun decodeFailure(bytes: ByteArray, e: Throwable): CodecException {
        val reason = when {
            e is StackOverflowError -> "the value nests too deeply"
            e.exceedsDepth() -> "the value nests deeper than ${registry.maxDepth} levels"
            else -> e.causes().filterIsInstance<RefusedBytesException>().firstOrNull()?.message
                ?: e.message ?: e.toString()
        }
        return CodecException("KryoCodec cannot decode ${bytes.size} bytes: $reason", e)
    }

    private fun Throwable.causes(): Sequence<Throwable> = generateSequence(this) { it.cause }

    /** Kryo's own depth check fired (it has no exception type of its own for it). */
    private fun Throwable.exceedsDepth(): Boolean =
        causes().any { it is KryoException && it.message.orEmpty().startsWith("Max depth exceeded") }

    /**
     * Collects the application's types for a [KryoCodec]. Not thread-safe; each [build] makes an
     * independent codec.
     */
    public class Builder internal constructor() {
        private val types = ArrayList<Class<*>>()
        private var maxDepth = DEFAULT_MAX_DEPTH

        /**
         * Allows [type] to be encoded and decoded, with the next id. Records are written through
         * their components and read through their canonical constructor; other classes field by
         * field (no constructor is needed). Enums are written by ordinal.
         *
         * @throws IllegalArgumentException if [type] is built in or already registered, is an
         *   interface, abstract class, array or collection (register the concrete element types
         *   and send a `java.util.List` instead)
         */
        public fun register(type: Class<*>): Builder {
            require(!KryoRegistry.isBuiltIn(type)) {
                "${type.name} is built into KryoCodec; do not register it"
            }
            require(type !in types) { "${type.name} is already registered" }
            require(!type.isArray) {
                "KryoCodec does not register arrays (${type.typeName}): register the element " +
                    "type and send a java.util.List (primitive arrays are built in)"
            }
            require(!Collection::class.java.isAssignableFrom(type)) {
                "KryoCodec does not register collection classes (${type.name}): any List, Set " +
                    "or Map is built in; register the element types"
            }
            require(type.isEnum || (!type.isInterface && !java.lang.reflect.Modifier.isAbstract(type.modifiers))) {
                "KryoCodec registers concrete classes only, not ${type.name}: a value is looked " +
                    "up by its runtime class, so register each concrete class that is sent"
            }
            types += type
            return this
        }

        /**
         * Sets how deeply values may nest (each record, collection or boxed value inside another
         * is one level); default [DEFAULT_MAX_DEPTH]. Deeper values fail to encode, and bytes
         * claiming deeper nesting fail to decode, instead of overflowing the stack.
         */
        public fun maxDepth(depth: Int): Builder {
            require(depth > 0) { "maxDepth must be positive, was $depth" }
            maxDepth = depth
            return this
        }

        /**
         * The codec. Its Kryo instances are created here once, so a type that cannot be
         * registered fails now.
         *
         * @throws IllegalArgumentException if a registered type cannot be serialized safely
         */
        public fun build(): KryoCodec = KryoCodec(KryoRegistry(types.toList(), maxDepth))
    }

    public companion object {
        /** Default of [Builder.maxDepth]. */
        public const val DEFAULT_MAX_DEPTH: Int = 64
        private const val MIN_POOLED = 8

        /** A codec with the built-in types only. */
        @JvmStatic
        public fun standard(): KryoCodec = Builder().build()

        /** A builder for a codec that also allows the application's types. */
        @JvmStatic
        public fun builder(): Builder = Builder()
    }
}

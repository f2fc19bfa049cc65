package dev.prime.optimus

import com.esotericsoftware.kryo.KryoException
import dev.prime.optimus.kryo.AllowList
import dev.prime.optimus.kryo.KryoRegistry
import dev.prime.optimus.kryo.KryoSession
import dev.prime.optimus.kryo.KryoSessionPool
import dev.prime.optimus.kryo.RefusedBytesException
import dev.prime.optimus.kryo.SealedHierarchy
import dev.prime.optimus.kryo.UnregisteredTypeException

/**
 * The default [OptimusCodec]: Kryo 5 with registration required.
 *
 * Only allowed types are written or read. Built in, with fixed ids: primitives and their
 * boxes, `String`, the primitive arrays, `BigInteger`, `BigDecimal`, any `java.util.List`,
 * `Set` and `Map` (read back as `ArrayList`, `LinkedHashSet`, `LinkedHashMap`: equal to what was
 * written, though not of the same class), `Optional`, `UUID`, `Instant`, `Duration`,
 * `LocalDate`, `LocalTime`, `LocalDateTime`, and Prime's [dev.prime.Token] (decoded as
 * `Token.INSTANCE`), [dev.prime.Tuple2]..[dev.prime.Tuple5], [dev.prime.Repeat] and [dev.prime.Tick].
 *
 * The application's types are allowed by class, by sealed hierarchy or by package with
 * [builder]; without configuration ([standard], what `new OptimusCore()` uses) the codec also
 * takes the records and enums a process sends (see [Builder.learnRecordsAndEnums]: a process
 * reads such a type only once it has sent one itself, which covers a topology in one process).
 * Ids depend only on what is allowed, never on the order of declaration or of first use, so
 * every process that allows the same types agrees, which [fingerprint] lets the core check.
 *
 * ```java
 * OptimusCodec codec = KryoCodec.builder()
 *     .allow(Pose.class)                     // one class
 *     .allow(Command.class)                  // a sealed interface: every class it permits
 *     .allowPackage("com.acme.robot")        // every class of the application's own package
 *     .build();
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
 * - **Safety.** Kryo reads only class ids of allowed types; its "class by name" form is refused,
 *   so bytes can never make the process load or create a class the application did not allow:
 *   a declared class, a class of an allowed package (found by its id among the package's class
 *   names, never by a name in the bytes), or a record or enum this process has sent itself.
 *   How the ids are chosen is the design note of `kryo/AllowList.kt`.
 *   Java serialization is never used (a type whose `@DefaultSerializer` asks for it is refused
 *   at registration). Every length prefix is checked against the bytes that remain before
 *   anything is allocated, nesting is limited ([Builder.maxDepth]), and any failure while
 *   reading becomes a [CodecException].
 * - **Threading.** Kryo instances are not thread-safe. Each call takes a Kryo with its buffers
 *   from a thread-safe pool and gives it back; a call that failed drops its Kryo instead, so no
 *   half-updated state is reused. A thread mostly gets back the Kryo it used last, from a slot
 *   of the pool no other thread touches, so threads sharing one codec do not slow each other
 *   down. Idle instances kept: at most one per slot (4 slots per processor, 16 to 64) and 4 per
 *   processor (≥ 8) more. An Optimus core's services and readers each keep one Kryo from the
 *   pool for their whole life, and `publishAll` one for its batch, so they take none per value.
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
     *   does not allow (the message shows the line that allows it), nests deeper than the limit,
     *   or cannot be written for another reason
     */
    override fun encode(value: Any): ByteArray = encode(value, 0)

    /** [encode] after [room] zero bytes, for a header the caller writes there (no copy to add one). */
    internal fun encode(value: Any, room: Int): ByteArray {
        val session = sessions.obtain()
        val bytes = encodeWith(session, value, room)
        sessions.free(session)
        return bytes
    }

    /** [encode] with [session], which a failure leaves in an unknown state: drop it then. */
    internal fun encodeWith(session: KryoSession, value: Any, room: Int): ByteArray = try {
        session.encode(value, room)
    } catch (e: RuntimeException) {
        throw encodeFailure(value, e)
    } catch (e: StackOverflowError) {
        throw encodeFailure(value, e)
    }

    /**
     * Decodes bytes written by an agreeing codec (same [fingerprint]).
     *
     * @throws CodecException if the bytes are empty, truncated, malformed, have bytes left over,
     *   hold `null`, or name a class this codec does not allow
     */
    override fun decode(bytes: ByteArray): Any = decode(bytes, 0, bytes.size)

    /** [decode] of the [length] bytes of [bytes] from [offset], read where they lie (no copy). */
    internal fun decode(bytes: ByteArray, offset: Int, length: Int): Any {
        if (length == 0) throw emptyBytes() // before a session is taken: a refusal here costs the pool none
        val session = sessions.obtain()
        val value = decodeWith(session, bytes, offset, length)
        sessions.free(session)
        return value
    }

    /** [decode] with [session], which a failure leaves in an unknown state: drop it then. */
    internal fun decodeWith(session: KryoSession, bytes: ByteArray, offset: Int, length: Int): Any {
        if (length == 0) throw emptyBytes()
        val value = try {
            session.decode(bytes, offset, length)
        } catch (e: RuntimeException) {
            throw decodeFailure(length, e)
        } catch (e: StackOverflowError) {
            throw decodeFailure(length, e)
        }
        return value ?: throw CodecException(
            "KryoCodec cannot decode $length bytes: they hold null, which the core never encodes",
        )
    }

    private fun emptyBytes() = CodecException("KryoCodec cannot decode 0 bytes: there is no value")

    /** A session of this codec's pool, for one user at a time until it gives it back with [free] ([HeldCodecSession]). */
    internal fun obtain(): KryoSession = sessions.obtain()

    /** Gives back a session [obtain] gave. */
    internal fun free(session: KryoSession) = sessions.free(session)

    /** Sessions idle in the pool now (for tests). */
    internal fun idleSessions(): Int = sessions.idle()

    /**
     * `"kryo-"` and 16 hex digits: a hash of [registeredTypes] and of the wire-format version.
     * Equal for codecs that allow the same types, packages and rules, in whatever order they
     * were declared, so they read each other's bytes.
     */
    override fun fingerprint(): String = registry.fingerprint

    /**
     * Every registration made when the codec was built as `"id class-name"`, ordered by id
     * (built-ins first, then the declared types sorted by name), then one line per rule that
     * admits types as they are met (`"package com.acme.robot"`, `"records and enums sent"`):
     * what [fingerprint] hashes.
     */
    public fun registeredTypes(): List<String> = registry.typeNames

    override fun toString(): String = "KryoCodec(${fingerprint()})"

    /**
     * Why a value of exactly [type] cannot be encoded (a sentence that starts "KryoCodec does not
     * allow it" and shows the line to add), or null if it can. A record or enum a default codec
     * learns is admitted by the lookup.
     */
    internal fun refusalOf(type: Class<*>): String? {
        val session = sessions.obtain()
        try {
            session.registration(type)
        } catch (e: UnregisteredTypeException) {
            return "KryoCodec does not allow it" + howToAllow(e.type)
        } catch (e: RuntimeException) {
            return e.message ?: e.toString()
        } finally {
            sessions.free(session)
        }
        return null
    }

    private fun encodeFailure(value: Any, e: Throwable): IllegalArgumentException {
        val unregistered = e.causes().filterIsInstance<UnregisteredTypeException>().firstOrNull()
        val type = value.javaClass.name
        if (unregistered != null) return IllegalArgumentException(notAllowed(value.javaClass, unregistered.type), e)
        val reason = when {
            e is StackOverflowError -> "it nests too deeply"
            e.exceedsDepth() -> "it nests deeper than ${registry.maxDepth} levels (or contains a cycle)"
            else -> e.message ?: e.toString()
        }
        return IllegalArgumentException("KryoCodec cannot encode a value of type $type: $reason", e)
    }

    /** What to say when [type], found in a value of class [valueType], is not allowed. */
    private fun notAllowed(valueType: Class<*>, type: Class<*>): String {
        val what = if (type == valueType) "the type is not allowed" else "it contains a ${type.name}, which is not allowed"
        return "KryoCodec cannot encode a value of type ${valueType.name}: $what${howToAllow(type)}"
    }

    /** Why [type] is refused under the learning rule, if that applies, and the line that allows it. */
    private fun howToAllow(type: Class<*>): String {
        val learned = if (registry.allowList.learnsRecordsAndEnums && !type.isRecord && !type.isEnum) {
            " (records and enums are accepted without configuration; ${type.simpleName} is neither)"
        } else ""
        val sourceName = type.canonicalName?.removePrefix(type.packageName + ".")
        val howTo = when {
            sourceName == null -> "Send a named record or class instead of this anonymous or local one, and allow it"
            type.packageName.isEmpty() -> "Allow it where the codec is built: " +
                "KryoCodec.builder().allow($sourceName.class) (Kotlin: allow($sourceName::class.java))"
            else -> "Allow it where the codec is built: " +
                "KryoCodec.builder().allow($sourceName.class) (Kotlin: allow($sourceName::class.java)), " +
                "or allow its whole package: KryoCodec.builder().allowPackage(\"${type.packageName}\")"
        }
        return "$learned. $howTo. Every process of the topology must allow the same types"
    }

    private fun decodeFailure(length: Int, e: Throwable): CodecException {
        val reason = when {
            e is StackOverflowError -> "the value nests too deeply"
            e.exceedsDepth() -> "the value nests deeper than ${registry.maxDepth} levels"
            else -> e.causes().filterIsInstance<RefusedBytesException>().firstOrNull()?.message
                ?: e.message ?: e.toString()
        }
        return CodecException("KryoCodec cannot decode $length bytes: $reason", e)
    }

    private fun Throwable.causes(): Sequence<Throwable> = generateSequence(this) { it.cause }

    /** Kryo's own depth check fired (it has no exception type of its own for it). */
    private fun Throwable.exceedsDepth(): Boolean =
        causes().any { it is KryoException && it.message.orEmpty().startsWith("Max depth exceeded") }

    /**
     * Collects the application's types for a [KryoCodec]. Not thread-safe; each [build] makes an
     * independent codec. The order of the calls does not matter: two builders given the same
     * types, packages and settings in any order make codecs with the same [fingerprint].
     */
    public class Builder internal constructor() {
        private val types = LinkedHashSet<Class<*>>()
        private val packages = LinkedHashSet<String>()
        private var learnsRecordsAndEnums = true
        private var maxDepth = DEFAULT_MAX_DEPTH

        /**
         * Allows [type] to be encoded and decoded. Records are written through their components
         * and read through their canonical constructor; other classes field by field (no
         * constructor is needed); enums by ordinal. A sealed class or interface (Java `sealed`,
         * Kotlin `sealed`) allows every concrete class it permits, through sealed subtypes too.
         *
         * @throws IllegalArgumentException if [type] is built in or already allowed, is an array
         *   or collection (allow the concrete element types and send a `java.util.List`
         *   instead), or is an interface or abstract class that is not sealed
         */
        public fun allow(type: Class<*>): Builder {
            require(!KryoRegistry.isBuiltIn(type)) {
                "${type.name} is built into KryoCodec; do not allow it"
            }
            require(type !in types) { "${type.name} is already allowed" }
            require(!type.isArray) {
                "KryoCodec does not allow arrays (${type.typeName}): allow the element " +
                    "type and send a java.util.List (primitive arrays are built in)"
            }
            require(!Collection::class.java.isAssignableFrom(type)) {
                "KryoCodec does not allow collection classes (${type.name}): any List, Set " +
                    "or Map is built in; allow the element types"
            }
            if (type.isSealed) {
                SealedHierarchy.concreteClasses(type).forEach { if (it !in types) types += it }
                return this
            }
            require(type.isEnum || (!type.isInterface && !java.lang.reflect.Modifier.isAbstract(type.modifiers))) {
                "KryoCodec allows concrete or sealed classes only, not ${type.name}: a value is " +
                    "looked up by its runtime class, so allow each concrete class that is sent " +
                    "(or make ${type.simpleName} sealed, or allow its package)"
            }
            types += type
            return this
        }

        /** The same as [allow] (its earlier name). */
        public fun register(type: Class<*>): Builder = allow(type)

        /**
         * Allows every concrete class of the package [name] (not of its subpackages): records,
         * enums and classes whose fields Kryo can write. Classes are admitted as they are sent
         * or read, each under an id computed from its name, so processes that allow the same
         * package agree on ids without declaring the classes one by one. Bytes can name only
         * classes of this package (found by listing the package's class files, loaded without
         * initialising them); a class in neither a directory nor a jar of the codec's class
         * loader (the building thread's context class loader) must be allowed by class.
         *
         * Allow the application's own packages only: every class in it may be created from
         * bytes that anybody with access to Redis could write.
         *
         * @throws IllegalArgumentException if [name] is not a package name, is the unnamed
         *   package, or a package of the JDK, Kotlin, Kryo or Prime
         */
        public fun allowPackage(name: String): Builder {
            require(PACKAGE_NAME.matches(name)) {
                "allowPackage takes a package name such as \"com.acme.robot\", not \"$name\""
            }
            require(name != "dev.prime" && FORBIDDEN_PACKAGES.none { name == it || name.startsWith("$it.") }) {
                "KryoCodec does not allow the package $name: it is not the application's own. " +
                    "Allow the classes that are sent with allow(...)"
            }
            packages += name
            return this
        }

        /**
         * Whether a record or enum that no other rule allows is accepted when this process
         * sends one (default `true`). Such a type is admitted by the process that sends it, under
         * an id computed from its name, and is readable in a process once that process has sent
         * one itself, or once an [OptimusCore] started with a block class that declares it
         * (`class Odometry implements Block<EncoderReading, Estimate>`): bytes alone never admit
         * it. That covers every value of a topology that runs in one process (each value is
         * encoded by the process that decodes it); for values sent between processes, allow the
         * types by class or package in every process (or declare them in block classes).
         * Set `false` to accept only what is allowed explicitly.
         */
        public fun learnRecordsAndEnums(enabled: Boolean): Builder {
            learnsRecordsAndEnums = enabled
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
         * The codec. Its Kryo instances are created here once, so a declared type that cannot be
         * registered fails now.
         *
         * @throws IllegalArgumentException if an allowed type cannot be serialized safely
         */
        public fun build(): KryoCodec {
            val loader = Thread.currentThread().contextClassLoader ?: KryoCodec::class.java.classLoader
            return KryoCodec(KryoRegistry(AllowList(types, packages.toSet(), learnsRecordsAndEnums, loader), maxDepth))
        }
    }

    public companion object {
        /** Default of [Builder.maxDepth]. */
        public const val DEFAULT_MAX_DEPTH: Int = 64
        private const val MIN_POOLED = 8

        private val PACKAGE_NAME = Regex("[\\p{L}_$][\\p{L}\\p{N}_$]*(\\.[\\p{L}_$][\\p{L}\\p{N}_$]*)*")
        private val FORBIDDEN_PACKAGES = listOf(
            "java", "javax", "jdk", "sun", "com.sun", "kotlin", "kotlinx", "com.esotericsoftware", "org.objenesis",
        ) + listOf(".optimus", ".liberty", ".radiant", ".spi", ".internal", ".topology", ".blocks", ".kotlin", ".test", ".mcap", ".bench")
            .map { "dev.prime$it" }

        /**
         * The codec `new OptimusCore()` uses: the built-in types, and the records and enums this
         * process sends (see [Builder.learnRecordsAndEnums]).
         */
        @JvmStatic
        public fun standard(): KryoCodec = Builder().build()

        /** A builder for a codec that also allows the application's types. */
        @JvmStatic
        public fun builder(): Builder = Builder()
    }
}

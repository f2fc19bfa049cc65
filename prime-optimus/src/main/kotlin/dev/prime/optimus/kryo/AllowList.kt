package dev.prime.optimus.kryo

import java.lang.reflect.Modifier
import java.security.MessageDigest
import java.util.concurrent.ConcurrentHashMap

/**
 * Which application types one codec accepts, and the ids they travel under.
 *
 * ## Design note
 * Every id must be the same in every process that declares the same allow-list, whatever order
 * the types were declared in, loaded in, or first sent in; and bytes must never make a process
 * create a class its own code did not allow.
 * - **Declared classes** (given by class, or the concrete classes a sealed type permits) are
 *   known when the codec is built. They are sorted by name and numbered from `FIRST_USER_ID`:
 *   small ids (one or two bytes on the wire) that depend only on the set of names.
 * - **Lazily admitted classes** (a class of an allowed package, or a record or enum this process
 *   sends, see [learnsRecordsAndEnums]) are not known when the codec is built. Their id is a
 *   hash of the class name (SHA-256, folded into [FIRST_HASH_ID] until 2^28: four bytes on the
 *   wire), so any two processes compute the same id for the same class without talking to each
 *   other. Collisions are detected, never resolved by order: a second class with an id already
 *   taken in this codec is refused with a message naming both (with 300 classes in the allowed
 *   packages the chance of any collision is about 1 in 6,000).
 * - **Reading** an id no registration covers looks the id up in [admitted] (classes this
 *   process has already admitted), then among the class *names* of the allowed packages, listed
 *   from this codec's class loader without loading anything ([PackageClassNames]); only a name
 *   whose hash matches and that lies in an allowed package is loaded (without initialising it)
 *   and checked like a class being sent. A record or enum admitted by [learnsRecordsAndEnums]
 *   is readable only once this process has sent one itself: bytes alone never admit a type.
 * - **Fingerprint**: the declared names with their ids, the allowed packages and whether
 *   records and enums are learned; the lazily admitted classes are not in it, since their ids
 *   follow from their names.
 *
 * Thread-safe: [admitted] is shared by every Kryo of the codec; the rest is immutable.
 */
internal class AllowList(
    declared: Collection<Class<*>>,
    val packages: Set<String>,
    val learnsRecordsAndEnums: Boolean,
    private val loader: ClassLoader,
) {
    /** Declared classes by name, each with its fixed id. */
    val declared: List<Pair<Int, Class<*>>> =
        declared.sortedBy { it.name }.mapIndexed { index, type -> FIRST_USER_ID + index to type }

    private val declaredTypes: Set<Class<*>> = this.declared.mapTo(HashSet()) { it.second }

    /** Lazily admitted classes by id: the same id can never name two classes in one codec. */
    private val admitted = ConcurrentHashMap<Int, Class<*>>()

    /** The allowed packages' class names, by hash id; listed on the first unknown id read. */
    private val packageNames: Map<Int, List<String>> by lazy {
        packages.flatMap { PackageClassNames.list(it, loader) }.distinct().groupBy(::hashId)
    }

    /** The rules that admit types lazily, in words (part of the fingerprint). */
    val rules: List<String> =
        packages.sorted().map { "package $it" } + (if (learnsRecordsAndEnums) listOf("records and enums sent") else emptyList())

    /**
     * The id under which [type] may be sent, registering it in [admitted], or null if no rule
     * admits it or it is declared (a declared class has its own id, never a hash id).
     *
     * @throws IllegalArgumentException if another admitted class has the same id
     */
    fun admit(type: Class<*>): Int? {
        if (type in declaredTypes || !admits(type)) return null
        val id = hashId(type.name)
        val other = admitted.putIfAbsent(id, type)
        require(other == null || other == type) { collision(id, type.name, other!!.name) }
        return id
    }

    /**
     * The class bytes may name by [id], or null if none: one this process admitted, or one of
     * an allowed package found by its name's hash.
     *
     * @throws RefusedBytesException if two classes of the allowed packages share [id]
     */
    fun classFor(id: Int): Class<*>? {
        admitted[id]?.let { return it }
        if (packages.isEmpty() || id < FIRST_HASH_ID) return null
        val names = packageNames[id] ?: return null
        if (names.size > 1) throw RefusedBytesException(collision(id, names[0], names[1]))
        val type = try {
            Class.forName(names[0], false, loader)
        } catch (e: ClassNotFoundException) {
            return null
        } catch (e: LinkageError) {
            return null
        }
        if (!inAllowedPackage(type)) return null
        return admit(type)?.let { admitted[it] }
    }

    private fun admits(type: Class<*>): Boolean {
        if (!isPlainClass(type)) return false
        if (inAllowedPackage(type)) return true
        return learnsRecordsAndEnums && (type.isRecord || type.isEnum)
    }

    private fun inAllowedPackage(type: Class<*>): Boolean = type.packageName in packages && isPlainClass(type)

    private fun collision(id: Int, first: String, second: String): String =
        "$first and $second have the same KryoCodec id $id (a hash of the class name), so " +
            "bytes could not tell them apart. Allow one of them by class " +
            "(KryoCodec.builder().allow(...)) or rename one"

    companion object {
        /** First id of [KryoRegistry]'s application types (declared ones, by name). */
        const val FIRST_USER_ID: Int = 100

        /** Lowest hash id; hash ids lie in `FIRST_HASH_ID until 2^28 - 2`, four varint bytes. */
        const val FIRST_HASH_ID: Int = 1 shl 21
        private const val HASH_SPAN = (1 shl 28) - 2 - FIRST_HASH_ID

        /** The id of a lazily admitted class, from its binary name alone. */
        fun hashId(className: String): Int {
            val digest = MessageDigest.getInstance("SHA-256").digest(className.toByteArray(Charsets.UTF_8))
            val folded = ((digest[0].toInt() and 0xff) shl 24) or ((digest[1].toInt() and 0xff) shl 16) or
                ((digest[2].toInt() and 0xff) shl 8) or (digest[3].toInt() and 0xff)
            return FIRST_HASH_ID + Math.floorMod(folded, HASH_SPAN)
        }

        /**
         * A named, concrete class whose instances Kryo writes as themselves: not an interface,
         * abstract class, array, primitive, anonymous, local, synthetic or hidden class, nor an
         * enum constant's body (Kryo writes those as their enum).
         */
        fun isPlainClass(type: Class<*>): Boolean =
            !type.isInterface && !type.isArray && !type.isPrimitive && !type.isAnonymousClass &&
                !type.isLocalClass && !type.isSynthetic && !type.isHidden &&
                (type.isEnum || !Modifier.isAbstract(type.modifiers)) &&
                !(Enum::class.java.isAssignableFrom(type) && !type.isEnum)
    }
}

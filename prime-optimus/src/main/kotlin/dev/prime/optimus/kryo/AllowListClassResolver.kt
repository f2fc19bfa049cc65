package dev.prime.optimus.kryo

import com.esotericsoftware.kryo.Kryo
import com.esotericsoftware.kryo.Registration
import com.esotericsoftware.kryo.io.Input
import com.esotericsoftware.kryo.util.DefaultClassResolver
import java.util.IdentityHashMap

/**
 * Kryo's class resolver, narrowed to an allow-list.
 *
 * - **Reading** accepts only ids of registered classes, or ids [allowList] maps to a class it
 *   admits (see its design note). Kryo's "class named by its name" form is refused outright, so
 *   bytes can never make this process load a class by a name they carry.
 * - **Writing** any `java.util.List`, `Set` or `Map` uses the one registration of that
 *   interface (ids do not depend on `List.of`'s or `Arrays.asList`'s private classes); the
 *   concrete class found is remembered so the next lookup is one map access. A class no
 *   registration covers is registered here under its hash id if [allowList] admits it.
 *
 * Not thread-safe, like the [Kryo] that owns it: one per pooled session.
 *
 * @param knownIds the registered ids in words, for the message about an unknown id
 */
internal class AllowListClassResolver(
    private val allowList: AllowList,
    private val knownIds: String,
) : DefaultClassResolver() {

    private val byInterface = IdentityHashMap<Class<*>, Registration>()

    override fun getRegistration(type: Class<*>?): Registration? {
        val direct = super.getRegistration(type)
        if (direct != null || type == null) return direct
        byInterface[type]?.let { return it }
        val container = when {
            List::class.java.isAssignableFrom(type) -> List::class.java
            Set::class.java.isAssignableFrom(type) -> Set::class.java
            Map::class.java.isAssignableFrom(type) -> Map::class.java
            else -> return allowList.admit(type)?.let { id -> registerAdmitted(type, id) }
        }
        val registration = super.getRegistration(container) ?: return null
        byInterface[type] = registration
        return registration
    }

    /** Tags on the wire: 0 null, 1 "class by name" (Kryo's NAME + 2), else registered id + 2. */
    override fun readClass(input: Input): Registration? {
        val tag = input.readVarInt(true)
        return when (tag) {
            Kryo.NULL.toInt() -> null
            NAME + 2 -> throw RefusedBytesException(
                "the bytes name a class by its name; this codec reads registered class ids only",
            )
            else -> idToRegistration.get(tag - 2) ?: admitted(tag - 2) ?: throw RefusedBytesException(
                "the bytes name class id ${tag - 2}, which this codec does not know (it knows ids " +
                    "$knownIds). The writer allowed a type this process has not: compare the two " +
                    "codecs' fingerprint(), and allow the same types in every process, e.g. " +
                    "KryoCodec.builder().allow(Pose.class) or .allowPackage(\"com.acme.robot\")" +
                    (if (allowList.learnsRecordsAndEnums) " (a record or enum is learned only from values this process sends itself, or from the types its block classes declare)" else ""),
            )
        }
    }

    private fun admitted(id: Int): Registration? {
        val type = allowList.classFor(id) ?: return null
        return try {
            registerAdmitted(type, id)
        } catch (e: IllegalArgumentException) {
            throw RefusedBytesException(e.message ?: e.toString())
        }
    }

    private fun registerAdmitted(type: Class<*>, id: Int): Registration {
        val registration = Registration(type, kryo.getDefaultSerializer(type), id)
        KryoRegistry.refuseJavaSerialization(registration)
        return register(registration)
    }
}

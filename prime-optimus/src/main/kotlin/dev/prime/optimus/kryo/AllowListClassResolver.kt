package dev.prime.optimus.kryo

import com.esotericsoftware.kryo.Kryo
import com.esotericsoftware.kryo.Registration
import com.esotericsoftware.kryo.io.Input
import com.esotericsoftware.kryo.util.DefaultClassResolver
import java.util.IdentityHashMap

/**
 * Kryo's class resolver, narrowed to an allow-list.
 *
 * - **Reading** accepts only ids of registered classes. Kryo's "class named by its name" form
 *   is refused outright, so bytes can never make this process load a class by name.
 * - **Writing** any `java.util.List`, `Set` or `Map` uses the one registration of that
 *   interface (ids do not depend on `List.of`'s or `Arrays.asList`'s private classes); the
 *   concrete class found is remembered so the next lookup is one map access.
 *
 * Not thread-safe, like the [Kryo] that owns it: one per pooled session.
 *
 * @param knownIds the registered ids in words, for the message about an unknown id
 */
internal class AllowListClassResolver(private val knownIds: String) : DefaultClassResolver() {

    private val byInterface = IdentityHashMap<Class<*>, Registration>()

    override fun getRegistration(type: Class<*>?): Registration? {
        val direct = super.getRegistration(type)
        if (direct != null || type == null) return direct
        byInterface[type]?.let { return it }
        val container = when {
            List::class.java.isAssignableFrom(type) -> List::class.java
            Set::class.java.isAssignableFrom(type) -> Set::class.java
            Map::class.java.isAssignableFrom(type) -> Map::class.java
            else -> return null
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
            else -> idToRegistration.get(tag - 2) ?: throw RefusedBytesException(
                "the bytes name class id ${tag - 2}, which this codec has not registered " +
                    "(it knows ids $knownIds). The writer registered other types: compare the " +
                    "two codecs' fingerprint() and register the same types in the same order",
            )
        }
    }
}

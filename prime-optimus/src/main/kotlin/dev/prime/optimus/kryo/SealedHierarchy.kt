package dev.prime.optimus.kryo

import java.lang.reflect.Modifier

/** The concrete classes a sealed class or interface permits, through sealed subtypes too. */
internal object SealedHierarchy {

    /**
     * Every concrete class below [root], sorted by name.
     *
     * @throws IllegalArgumentException if a permitted subtype is abstract or an interface but not
     *   sealed itself (its subclasses cannot be listed), naming it
     */
    fun concreteClasses(root: Class<*>): List<Class<*>> {
        val found = sortedMapOf<String, Class<*>>()
        val pending = ArrayDeque(listOf(root))
        while (pending.isNotEmpty()) {
            val type = pending.removeFirst()
            if (type.isSealed) {
                type.permittedSubclasses.orEmpty().forEach { pending.addLast(it) }
                if (type.isInterface || Modifier.isAbstract(type.modifiers)) continue
            } else {
                require(!type.isInterface && !Modifier.isAbstract(type.modifiers)) {
                    "KryoCodec cannot allow every class of the sealed ${root.name}: it permits " +
                        "${type.name}, which is abstract but not sealed, so its subclasses cannot be " +
                        "listed. Allow its concrete subclasses too, or its package"
                }
            }
            found[type.name] = type
        }
        return found.values.toList()
    }
}

package dev.prime.optimus.kryo

import com.esotericsoftware.kryo.Kryo
import com.esotericsoftware.kryo.Serializer
import com.esotericsoftware.kryo.io.Input
import com.esotericsoftware.kryo.io.Output

/*
 * Serializers for any java.util.List, Set and Map: size, then each element with its class id.
 * Whatever class was written (ArrayList, List.of, Arrays.asList, an unmodifiable view, Kotlin's
 * listOf), reading gives an ArrayList, LinkedHashSet or LinkedHashMap (iteration order kept),
 * which is equal to the original under the collection contracts. The size is checked against
 * the remaining bytes before anything is allocated, and pre-sizing is capped, so a crafted size
 * costs nothing.
 */

/** Pre-size at most this many slots; larger collections grow as elements actually arrive. */
private const val MAX_PRESIZE = 1024

/**
 * Writes any collection as its size and elements; reads the collection [create] makes of a
 * (capped) expected size: an [ArrayList] for lists, a [LinkedHashSet] for sets.
 */
internal class CollectionSerializer(
    private val what: String,
    private val create: (Int) -> MutableCollection<Any?>,
) : Serializer<Collection<*>>(false, false) {
    override fun write(kryo: Kryo, output: Output, collection: Collection<*>) {
        output.writeVarInt(collection.size, true)
        for (element in collection) kryo.writeClassAndObject(output, element)
    }

    override fun read(kryo: Kryo, input: Input, type: Class<out Collection<*>>): Collection<*> {
        val size = input.readVarInt(true)
        input.requireAvailable(size, 1, what)
        val collection = create(minOf(size, MAX_PRESIZE))
        repeat(size) { collection.add(kryo.readClassAndObject(input)) }
        return collection
    }

    companion object {
        /** Any `java.util.List`, read as an [ArrayList]. */
        fun ofLists() = CollectionSerializer("a list") { ArrayList(it) }

        /** Any `java.util.Set`, read as a [LinkedHashSet]. */
        fun ofSets() = CollectionSerializer("a set") { LinkedHashSet(it) }
    }
}

/** Writes any `java.util.Map`; reads a [LinkedHashMap]. */
internal class MapSerializer : Serializer<Map<*, *>>(false, false) {
    override fun write(kryo: Kryo, output: Output, map: Map<*, *>) {
        output.writeVarInt(map.size, true)
        for ((key, value) in map) {
            kryo.writeClassAndObject(output, key)
            kryo.writeClassAndObject(output, value)
        }
    }

    override fun read(kryo: Kryo, input: Input, type: Class<out Map<*, *>>): Map<*, *> {
        val size = input.readVarInt(true)
        input.requireAvailable(size, 2, "a map")
        val map = LinkedHashMap<Any?, Any?>(minOf(size, MAX_PRESIZE))
        repeat(size) {
            val key = kryo.readClassAndObject(input)
            map[key] = kryo.readClassAndObject(input)
        }
        return map
    }
}

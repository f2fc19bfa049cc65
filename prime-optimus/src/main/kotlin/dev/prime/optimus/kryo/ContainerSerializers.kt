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

/** Writes any `java.util.List`; reads an [ArrayList]. */
internal class ListSerializer : Serializer<List<*>>(false, false) {
    override fun write(kryo: Kryo, output: Output, list: List<*>) {
        output.writeVarInt(list.size, true)
        for (element in list) kryo.writeClassAndObject(output, element)
    }

    override fun read(kryo: Kryo, input: Input, type: Class<out List<*>>): List<*> {
        val size = input.readVarInt(true)
        input.requireAvailable(size, 1, "a list")
        val list = ArrayList<Any?>(minOf(size, MAX_PRESIZE))
        repeat(size) { list.add(kryo.readClassAndObject(input)) }
        return list
    }
}

/** Writes any `java.util.Set`; reads a [LinkedHashSet]. */
internal class SetSerializer : Serializer<Set<*>>(false, false) {
    override fun write(kryo: Kryo, output: Output, set: Set<*>) {
        output.writeVarInt(set.size, true)
        for (element in set) kryo.writeClassAndObject(output, element)
    }

    override fun read(kryo: Kryo, input: Input, type: Class<out Set<*>>): Set<*> {
        val size = input.readVarInt(true)
        input.requireAvailable(size, 1, "a set")
        val set = LinkedHashSet<Any?>(minOf(size, MAX_PRESIZE))
        repeat(size) { set.add(kryo.readClassAndObject(input)) }
        return set
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

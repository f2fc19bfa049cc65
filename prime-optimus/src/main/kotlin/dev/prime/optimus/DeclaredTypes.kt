package dev.prime.optimus

import dev.prime.Block
import java.lang.reflect.Modifier
import java.lang.reflect.ParameterizedType
import java.util.concurrent.ConcurrentLinkedQueue

/**
 * The value types the topology declares, checked against the codec at start.
 *
 * A block that is a class implementing `Block<I, O>` with concrete type arguments (such as
 * `Odometry implements Block<EncoderReading, Estimate>`) declares the types its service takes and
 * gives; a lambda declares none (its types are erased). At start each declared type that values
 * must have exactly (a record, an enum or a final class) is looked up in a [KryoCodec]: one it
 * does not allow fails the start with the codec's message, instead of the first value sent.
 * The lookup also admits the records and enums a default codec learns, so a process that hosts
 * such a service reads its input before it has sent one itself.
 *
 * Thread-safe: chains may be declared from several threads.
 */
internal class DeclaredTypes {
    private val declared = ConcurrentLinkedQueue<Declared>()

    private class Declared(val service: String, val block: Class<*>, val types: List<Class<*>?>)

    /** Notes the types [block] declares for [service], if its class declares any. */
    fun note(service: String, block: Block<*, *>) {
        val types = blockTypeArguments(block.javaClass) ?: return
        declared += Declared(service, block.javaClass, types)
    }

    /**
     * Checks every declared type against [codec] (other codecs than [KryoCodec] are not checked).
     *
     * @throws IllegalStateException for the first service whose declared type the codec refuses
     */
    fun check(core: String, codec: OptimusCodec) {
        if (codec !is KryoCodec) return
        for (entry in declared) {
            entry.types.forEachIndexed { index, type ->
                if (type == null || !isExact(type)) return@forEachIndexed
                val refusal = codec.refusalOf(type) ?: return@forEachIndexed
                val generic = entry.types.joinToString(", ", "Block<", ">") { it?.simpleName ?: "?" }
                throw IllegalStateException(
                    "core '$core' cannot start: service '${entry.service}' ${if (index == 0) "takes" else "gives"} " +
                        "${type.name} (${entry.block.simpleName} implements $generic), and $refusal",
                )
            }
        }
    }

    private fun isExact(type: Class<*>): Boolean =
        !type.isPrimitive && !type.isArray && !type.isInterface &&
            (type.isEnum || type.isRecord || Modifier.isFinal(type.modifiers))

    private companion object {
        /** `I` and `O` of the `Block<I, O>` [type] implements (null where not a class), or null. */
        fun blockTypeArguments(type: Class<*>): List<Class<*>?>? {
            var current: Class<*>? = type
            while (current != null && current != Any::class.java) {
                for (implemented in current.genericInterfaces) {
                    if (implemented is ParameterizedType && implemented.rawType == Block::class.java) {
                        return implemented.actualTypeArguments.map { it as? Class<*> }
                    }
                }
                current = current.superclass
            }
            return null
        }
    }
}

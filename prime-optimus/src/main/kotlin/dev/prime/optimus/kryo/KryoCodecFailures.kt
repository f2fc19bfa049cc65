package dev.prime.optimus.kryo

import com.esotericsoftware.kryo.KryoException

/**
 * Kryo was asked to write an instance of [type], which no registration covers. Thrown from deep
 * inside a write (possibly wrapped by Kryo's serializers); `KryoCodec.encode` finds it in the
 * cause chain and turns it into an [IllegalArgumentException] that says how to register the type.
 */
internal class UnregisteredTypeException(val type: Class<*>) :
    IllegalArgumentException("type not registered: ${type.name}") {
    private companion object {
        private const val serialVersionUID: Long = 1L
    }
}

/**
 * The bytes being read are malformed or name something this codec must not create; the message
 * says what. A [KryoException], so Kryo's serializers add their trace and pass it on.
 */
internal class RefusedBytesException(message: String) : KryoException(message) {
    private companion object {
        private const val serialVersionUID: Long = 1L
    }
}

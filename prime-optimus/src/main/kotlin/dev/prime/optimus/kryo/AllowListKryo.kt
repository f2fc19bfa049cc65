package dev.prime.optimus.kryo

import com.esotericsoftware.kryo.Kryo
import com.esotericsoftware.kryo.Registration

/**
 * A [Kryo] whose "class not registered" failure is an [UnregisteredTypeException] naming the
 * class, so the codec can tell it apart from other write failures however deep it happened.
 * Not thread-safe (no Kryo is).
 */
internal class AllowListKryo(resolver: AllowListClassResolver) : Kryo(resolver, null) {

    override fun getRegistration(type: Class<*>?): Registration {
        try {
            return super.getRegistration(type)
        } catch (e: IllegalArgumentException) {
            if (type != null && classResolver.getRegistration(type) == null) {
                throw UnregisteredTypeException(type)
            }
            throw e
        }
    }
}

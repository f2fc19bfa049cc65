package dev.prime.optimus

import dev.prime.ValueCodec

/**
 * Turns the values that travel between Optimus services into bytes and back.
 *
 * Every value that crosses Redis (a chain's input and output, a source's values) goes through
 * the core's codec. All processes that share a topology must use codecs that agree: the same
 * allowed types. [fingerprint] lets the core check that at start.
 *
 * ## Contract
 * - **Threading.** Both methods are called concurrently from many threads; implementations are
 *   thread-safe.
 * - **Safety.** [decode] reads bytes that anybody with access to Redis could have written. It
 *   must never run Java native deserialization, and it must only create instances of types the
 *   application allowed.
 * - **Nulls.** Neither method sees `null`: the core encodes `null` outputs itself.
 * - **Exceptions.** [encode] throws [IllegalArgumentException] for a value it cannot encode,
 *   with a message that says how to allow it; [decode] throws [CodecException] for bytes it
 *   cannot or must not decode. The core sends undecodable input to a dead-letter list (a
 *   reader skips it with a WARN). Any other exception [decode] throws is taken the same way,
 *   for that value only: it neither stops a service nor reaches a reader's caller.
 *
 * Every Optimus codec is a [ValueCodec], so the in-memory media can copy values through it
 * (`CoreConfig.builder().copyValues(KryoCodec.standard())`) and fail in a test the way Optimus
 * would on a type the codec refuses.
 */
public interface OptimusCodec : ValueCodec {

    /**
     * Encodes one value.
     *
     * @throws IllegalArgumentException if the value's type is not allowed
     */
    override fun encode(value: Any): ByteArray

    /**
     * Decodes one value written by [encode] of an agreeing codec.
     *
     * @throws CodecException if the bytes are malformed or name a type that is not allowed
     */
    override fun decode(bytes: ByteArray): Any

    /**
     * A short text that is equal for two codecs exactly when they read each other's bytes, such
     * as a hash of the allowed type names with their ids.
     */
    public fun fingerprint(): String
}

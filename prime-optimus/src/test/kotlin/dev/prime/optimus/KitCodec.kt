package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.ValueCodec

/**
 * A [ValueCodec] of the conformance kit as this core's codec, for the kit's cores whose values
 * cross services through a codec it gives (`ConformanceBase.newCoreWithCodec`): Optimus copies
 * every value through its own codec, so the kit's codec must be that codec.
 */
internal class KitCodec(private val codec: ValueCodec) : OptimusCodec {
    override fun encode(value: Any): ByteArray = codec.encode(value)

    override fun decode(bytes: ByteArray): Any = codec.decode(bytes)

    override fun fingerprint(): String = "kit:$codec"

    override fun toString(): String = codec.toString()
}

/** This builder with [config]'s copy codec, if it has one, as the core's codec. */
internal fun OptimusCore.Builder.kitCodecOf(config: CoreConfig): OptimusCore.Builder =
    config.valueCopies()?.let { codec(KitCodec(it)) } ?: this

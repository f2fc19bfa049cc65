package dev.prime.kotlin

import dev.prime.CoreConfig
import dev.prime.PrimeCore
import dev.prime.ValueCodec
import dev.prime.liberty.LibertyCore
import dev.prime.optimus.EmbeddedRedis
import dev.prime.optimus.FaultProxy
import dev.prime.optimus.OptimusCodec
import dev.prime.optimus.OptimusCore
import dev.prime.radiant.RadiantCore
import redis.clients.jedis.Jedis
import java.net.URI

/** The media the kits of this module run on: each makes a new, not yet started core. */
internal interface Media {
    fun newCore(config: CoreConfig = CoreConfig.defaults()): PrimeCore

    /**
     * A new core that turns every published value into bytes with [config]'s copy codec
     * (`CoreConfig.Builder.copyValues`), so a codec's failure in a publish is seen on every media:
     * Liberty and Radiant copy through it anyway; Optimus, which copies every value through its own
     * codec, gets it as that codec.
     */
    fun newCoreWithCodec(config: CoreConfig): PrimeCore = newCore(config)

    /**
     * Whether a chain's block runs in a service that takes one call after the other (Optimus),
     * so a call made while the service is busy waits in its input; otherwise each call runs the
     * block on its caller's thread at once (Liberty, Radiant).
     */
    val callsQueueAtTheService: Boolean get() = false

    /**
     * How many readers [source] of [core] keeps values for, where the media can tell (Optimus: the
     * source's reader set in Redis); `null` where a reader costs its source nothing to keep
     * (Liberty and Radiant: readers share one ring of retained values).
     */
    fun readersKept(core: PrimeCore, source: String): Long? = null

    /** Whether a read before `start()` fails at once with `IllegalStateException` (Optimus) rather than waiting for the start. */
    val refusesReadsBeforeStart: Boolean get() = false
}

internal object Liberty : Media {
    override fun newCore(config: CoreConfig): PrimeCore = LibertyCore(config)
}

internal object Radiant : Media {
    override fun newCore(config: CoreConfig): PrimeCore = RadiantCore(config)
}

/** Optimus on one embedded Redis for this test JVM (each core is its own namespace on it). */
internal object Optimus : Media {
    internal val redis: EmbeddedRedis by lazy { EmbeddedRedis.start() }

    override fun newCore(config: CoreConfig): PrimeCore =
        OptimusCore.builder().config(config).redis(redis.uri).build()

    override fun newCoreWithCodec(config: CoreConfig): PrimeCore =
        OptimusCore.builder().config(config).redis(redis.uri).codecOf(config).build()

    override val callsQueueAtTheService: Boolean get() = true

    override val refusesReadsBeforeStart: Boolean get() = true

    override fun readersKept(core: PrimeCore, source: String): Long? =
        Jedis(URI(redis.uri)).use { it.scard("prime:{${core.name()}}:src:$source:readers") }
}

/**
 * The awkward variant: Optimus on the same Redis through a proxy that holds every reply back half
 * a millisecond (as the conformance kit's slow-Redis variant), so values are in flight while
 * flows collect, suspending calls wait and cores close.
 */
internal object OptimusSlowRedis : Media by Optimus {
    override fun newCore(config: CoreConfig): PrimeCore =
        OptimusCore.builder().config(config).redis(FaultProxy.slowLinkTo(Optimus.redis.uri)).build()

    override fun newCoreWithCodec(config: CoreConfig): PrimeCore =
        OptimusCore.builder().config(config).redis(FaultProxy.slowLinkTo(Optimus.redis.uri)).codecOf(config).build()
}

/** This builder with [config]'s copy codec as the core's codec. */
private fun OptimusCore.Builder.codecOf(config: CoreConfig): OptimusCore.Builder =
    codec(CopyCodec(requireNotNull(config.valueCopies()) { "newCoreWithCodec needs a config with copyValues(codec)" }))

/** A copy codec of a test as an Optimus core's codec. */
private class CopyCodec(private val codec: ValueCodec) : OptimusCodec {
    override fun encode(value: Any): ByteArray = codec.encode(value)

    override fun decode(bytes: ByteArray): Any = codec.decode(bytes)

    override fun fingerprint(): String = "test:$codec"

    override fun toString(): String = codec.toString()
}

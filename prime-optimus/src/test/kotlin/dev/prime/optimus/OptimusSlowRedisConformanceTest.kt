package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.PrimeCore
import dev.prime.conformance.MediaConformance
import dev.prime.conformance.SourceConformance

/**
 * The awkward variant: the whole conformance kit again, through a proxy that delays every reply
 * of Redis by half a millisecond, so that values are in flight while services batch, readers
 * poll and cores close.
 */
class OptimusSlowRedisConformanceTest : MediaConformance {
    override fun newCore(config: CoreConfig): PrimeCore =
        OptimusCore.builder().config(config).redis(slowUrl).build()

    override fun servicesOfLinkedChain(chains: Int): Int = chains

    /** The kit's codec is the core's codec: Optimus copies every value through its own. */
    override fun newCoreWithCodec(config: CoreConfig): PrimeCore =
        OptimusCore.builder().config(config).redis(slowUrl).kitCodecOf(config).build()

    /** A service's input holds its queue limit, not the retention. */
    override fun newCoreWithServiceInputCapacity(config: CoreConfig, capacity: Int): PrimeCore =
        OptimusCore.builder().config(config).redis(slowUrl).queueLimit(capacity).build()

    /** Blocks run in services: a VirtualMachineError reaches the caller promptly, then ends the service. */
    override fun blocksRunOnTheCallersThread(): Boolean = false

    /** Cores of one name on one Redis share a topology; each runs only the services it hosts. */
    override fun newCoreHosting(config: CoreConfig, services: Set<String>): PrimeCore =
        OptimusCore.builder().config(config).redis(slowUrl).hosts(services).build()

    private companion object {
        val slowUrl: String get() = FaultProxy.slowLinkTo(TestRedis.url)
    }

    /** A value on which a service's block threw is dead-lettered. */
    override fun failedServiceValuesAreDeadLettered(): Boolean = true

    /** A publish before start() fails at once, like a call and a read. */
    override fun publishesBeforeStartWait(): Boolean = false

    /** The slow link's proxy starts threads of its own for each connection the core opens. */
    override fun isFixtureThread(name: String): Boolean = name.startsWith("fault-proxy-")

    /** A topology lives in Redis: a later core of the same name carries on. */
    override fun topologyOutlivesItsCores(): Boolean = true

    /** Sources live in Redis: the core talks to it through a proxy that can freeze. */
    override fun newCoreWithAnOutage(config: CoreConfig): SourceConformance.Outage = OutageCore(config, FaultProxy(TestRedis.url, FaultProxy.SLOW_REPLY_NANOS))
}

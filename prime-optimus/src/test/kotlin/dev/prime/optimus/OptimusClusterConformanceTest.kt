package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.PrimeCore
import dev.prime.conformance.MediaConformance

/**
 * The whole conformance kit on a real Redis Cluster of 3 masters and 3 replicas ([TestCluster]),
 * through a `redis-cluster://` URL: every core's topology in the hash slot of its name, on the
 * master that holds it.
 */
class OptimusClusterConformanceTest : MediaConformance {
    override fun newCore(config: CoreConfig): PrimeCore = OptimusCore.builder().config(config).redis(TestCluster.url).build()

    override fun servicesOfLinkedChain(chains: Int): Int = chains

    /** The kit's codec is the core's codec: Optimus copies every value through its own. */
    override fun newCoreWithCodec(config: CoreConfig): PrimeCore =
        OptimusCore.builder().config(config).redis(TestCluster.url).kitCodecOf(config).build()

    /** A service's input holds its queue limit, not the retention. */
    override fun newCoreWithServiceInputCapacity(config: CoreConfig, capacity: Int): PrimeCore =
        OptimusCore.builder().config(config).redis(TestCluster.url).queueLimit(capacity).build()

    /** Blocks run in services: a VirtualMachineError reaches the caller promptly, then ends the service. */
    override fun blocksRunOnTheCallersThread(): Boolean = false

    /** Cores of one name on one cluster share a topology; each runs only the services it hosts. */
    override fun newCoreHosting(config: CoreConfig, services: Set<String>): PrimeCore =
        OptimusCore.builder().config(config).redis(TestCluster.url).hosts(services).build()

    /** A value on which a service's block threw is dead-lettered. */
    override fun failedServiceValuesAreDeadLettered(): Boolean = true

    /** A publish before start() fails at once, like a call and a read. */
    override fun publishesBeforeStartWait(): Boolean = false

    /** A topology lives in Redis: a later core of the same name carries on. */
    override fun topologyOutlivesItsCores(): Boolean = true
}

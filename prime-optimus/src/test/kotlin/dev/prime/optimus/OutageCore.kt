package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.PrimeCore
import dev.prime.conformance.SourceConformance

/**
 * The kit's core with an outage on Optimus: a core of [config] that talks to Redis through
 * [proxy], which [cut] freezes and [mend] thaws; closing it thaws and closes the proxy too.
 */
internal class OutageCore(config: CoreConfig, private val proxy: FaultProxy) : SourceConformance.Outage {
    private val core = OptimusCore.builder().config(config).redis(proxy.url).build()

    override fun core(): PrimeCore = core

    override fun cut() = proxy.freeze()

    override fun mend() = proxy.thaw()

    override fun close() {
        proxy.thaw()
        try {
            core.close()
        } finally {
            proxy.close()
        }
    }
}

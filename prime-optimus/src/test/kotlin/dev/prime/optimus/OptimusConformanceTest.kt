package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.PrimeCore
import dev.prime.conformance.MediaConformance

/** The whole conformance kit on Optimus, every core a namespace of one embedded Redis. */
class OptimusConformanceTest : MediaConformance {
    override fun newCore(config: CoreConfig): PrimeCore = TestRedis.core(config)
}

package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.Source
import java.time.Duration

/**
 * The topology of the competing-consumer tests and [ConsumerWorkerMain]: source "numbers" →
 * service [SERVICE] (a block that sleeps, then returns its input) → its output source.
 */
internal object CompetingTopology {
    const val SERVICE = "slow"
    const val RETENTION = 100_000
    val LEASE: Duration = Duration.ofSeconds(1)

    /** A core of topology [name] on [redis] hosting [SERVICE] with [mode] (`null`: hosting nothing). */
    fun core(redis: String, name: String, mode: Hosting?): OptimusCore {
        val builder = OptimusCore.builder()
            .config(CoreConfig.builder().name(name).sourceRetention(RETENTION).build())
            .redis(redis)
            .leaseTime(LEASE)
        return if (mode == null) builder.hosts(emptyList()).build() else builder.hosts(SERVICE).hosting(SERVICE, mode).build()
    }

    /** Declares the topology; the block sleeps [blockMillis] and tells [seen] each value. */
    fun declare(core: OptimusCore, blockMillis: Long, seen: (Int) -> Unit = {}): Pair<EventBlock<Int>, Source<Int>> {
        val numbers = EventBlock<Int>()
        val output = core.source("numbers", numbers).then(
            core.chain(SERVICE) { x: Int ->
                if (blockMillis > 0) Thread.sleep(blockMillis)
                seen(x)
                x
            },
        )
        return numbers to output
    }
}

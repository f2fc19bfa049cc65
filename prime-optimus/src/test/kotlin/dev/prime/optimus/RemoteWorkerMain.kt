package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import kotlin.system.exitProcess

/**
 * The second process of [TwoProcessTest]: `RemoteWorkerMain REDIS_URL CORE_NAME` declares
 * [TwoProcessTopology] on that Redis under that core name, hosts only
 * [TwoProcessTopology.WORKER_SERVICES], prints `READY` once they run, and stops (printing
 * `STOPPED`) when its input ends or gives a line `STOP`.
 */
object RemoteWorkerMain {
    @JvmStatic
    fun main(args: Array<String>) {
        if (args.size != 2) {
            System.err.println("usage: RemoteWorkerMain REDIS_URL CORE_NAME")
            exitProcess(2)
        }
        OptimusCore.builder()
            .config(CoreConfig.builder().name(args[1]).build())
            .redis(args[0])
            .hosts(TwoProcessTopology.WORKER_SERVICES)
            .build()
            .use { core ->
                TwoProcessTopology.declare(core, EventBlock())
                core.start()
                println("READY hosting ${core.serviceNames().sorted()}")
                System.out.flush()
                generateSequence { readlnOrNull() }.firstOrNull { it.trim() == "STOP" }
            }
        println("STOPPED")
    }
}

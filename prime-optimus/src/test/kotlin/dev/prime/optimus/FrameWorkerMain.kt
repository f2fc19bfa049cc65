package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import java.time.Duration
import java.util.concurrent.CountDownLatch
import java.util.concurrent.atomic.AtomicInteger
import kotlin.system.exitProcess

/**
 * The worker of [FrameKillTest]: `FrameWorkerMain REDIS_URL CORE_NAME STALL_AT` declares
 * [FrameKillTest.declare], hosts its service "times10" with a 1 s lease and prints `READY`. With
 * `STALL_AT` > 0 its block, at its `STALL_AT`-th value, prints `STALLED` and never returns (the
 * test then kills the JVM in the middle of a frame). On a line `STOP` it prints `PROCESSED n`, the
 * values its block ran on, and ends.
 */
object FrameWorkerMain {
    @JvmStatic
    fun main(args: Array<String>) {
        if (args.size != 3) {
            System.err.println("usage: FrameWorkerMain REDIS_URL CORE_NAME STALL_AT")
            exitProcess(2)
        }
        val stallAt = args[2].toInt()
        val processed = AtomicInteger()
        val never = CountDownLatch(1)
        OptimusCore.builder()
            .config(CoreConfig.builder().name(args[1]).sourceRetention(FrameKillTest.RETENTION).build())
            .redis(args[0])
            .hosts(FrameKillTest.SERVICE)
            .leaseTime(Duration.ofSeconds(1))
            .build()
            .use { core ->
                FrameKillTest.declare(core) { x ->
                    if (processed.incrementAndGet() == stallAt) {
                        println("STALLED at $x")
                        System.out.flush()
                        never.await()
                    }
                    x * 10
                }
                core.start()
                println("READY")
                System.out.flush()
                generateSequence { readlnOrNull() }.firstOrNull { it.trim() == "STOP" }
                println("PROCESSED ${processed.get()}")
                System.out.flush()
            }
    }
}

package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import java.time.Duration
import kotlin.system.exitProcess

/**
 * The worker process of the lease tests: `LeaseWorkerMain REDIS_URL CORE_NAME LEASE_MS MODE [N [M]]`.
 * - `readers N`: declares a source "numbers", makes N readers of it (which read nothing) and
 *   starts, hosting nothing; prints `READY`.
 * - `host [MS [SQUARE_MS]]`: declares [TwoProcessTopology] hosting
 *   [TwoProcessTopology.WORKER_SERVICES] (its "double" taking MS milliseconds per value and its
 *   "square" SQUARE_MS per call, default 0), prints `DECLARED`, waits for a line `START`, starts,
 *   and prints `READY <ms start() took>`.
 *
 * Then it waits until its input ends or gives a line `STOP`, and prints `STOPPED`. A failing
 * `start()` prints `FAILED <message>` and exits with 1.
 */
object LeaseWorkerMain {
    /** Starts a `host` worker with [args] and waits until it has declared the topology; it hosts nothing until [startHosting]. */
    internal fun declaredHost(vararg args: String): WorkerProcess {
        val worker = WorkerProcess.start(LeaseWorkerMain::class.java, *args)
        try {
            worker.awaitLine("DECLARED")
        } catch (e: Throwable) {
            worker.close()
            throw e
        }
        return worker
    }

    /** Tells a worker of [declaredHost] to start hosting, and waits until it has; its `READY` line. */
    internal fun startHosting(worker: WorkerProcess): String {
        worker.send("START")
        return worker.awaitLine("READY")
    }

    @JvmStatic
    fun main(args: Array<String>) {
        if (args.size < 4) {
            System.err.println("usage: LeaseWorkerMain REDIS_URL CORE_NAME LEASE_MS readers N | host [MS [SQUARE_MS]]")
            exitProcess(2)
        }
        val mode = args[3]
        val builder = OptimusCore.builder()
            .config(CoreConfig.builder().name(args[1]).build())
            .redis(args[0])
            .leaseTime(Duration.ofMillis(args[2].toLong()))
        builder.hosts(if (mode == "host") TwoProcessTopology.WORKER_SERVICES else emptyList()).build().use { core ->
            when (mode) {
                "readers" -> {
                    val numbers = core.source("numbers", EventBlock<Int>())
                    val readers = (0 until args[4].toInt()).map { numbers.reader() }
                    core.start()
                    println("READY with ${readers.size} readers")
                }
                "host" -> {
                    TwoProcessTopology.declare(core, EventBlock(), args.getOrNull(4)?.toLong() ?: 0, args.getOrNull(5)?.toLong() ?: 0)
                    println("DECLARED")
                    System.out.flush()
                    if (generateSequence { readlnOrNull() }.firstOrNull { it.trim() == "START" } == null) return
                    val started = System.nanoTime()
                    try {
                        core.start()
                    } catch (e: IllegalStateException) {
                        println("FAILED ${e.message}")
                        System.out.flush()
                        exitProcess(1)
                    }
                    println("READY ${(System.nanoTime() - started) / 1_000_000}")
                }
                else -> {
                    System.err.println("unknown mode $mode")
                    exitProcess(2)
                }
            }
            System.out.flush()
            generateSequence { readlnOrNull() }.firstOrNull { it.trim() == "STOP" }
        }
        println("STOPPED")
    }
}

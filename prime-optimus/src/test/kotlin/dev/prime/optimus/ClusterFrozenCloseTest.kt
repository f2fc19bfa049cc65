package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration
import java.util.concurrent.TimeUnit
import java.util.concurrent.locks.LockSupport

/**
 * A core on a real Redis Cluster (3 masters, 3 replicas) whose every node stops answering (each
 * redis-server stopped with SIGSTOP: connections open, no answer, as in a partition) is closed
 * while one of its threads looks up the master of its slot again (its connection timed out): the
 * close ends that lookup, returns within its shutdown timeout and leaves no thread of the core.
 */
class ClusterFrozenCloseTest {

    @Test
    fun closeEndsAMasterLookupOnAFrozenClusterInTime() {
        LocalRedisCluster.start().use { cluster ->
            val pids = cluster.nodes.map { node ->
                node.jedis().use { Regex("process_id:(\\d+)").find(it.info("server"))!!.groupValues[1] }
            }
            val name = "cluster-frozen-close"
            val shutdown = Duration.ofSeconds(1)
            val config = CoreConfig.builder().name(name).shutdownTimeout(shutdown).build()
            val core = OptimusCore.builder().config(config).redis(cluster.url).build()
            try {
                core.source("ids", EventBlock<Long>()).reader()
                assertEquals(1L, core.chain("echo") { x: Long -> x }.toBlock().let { core.start(); it.process(1L) })
                for (pid in pids) signal("STOP", pid)
                // a thread of the core finds its connection timed out and looks the master up again
                val lookupSeen = awaitLookup(name, Duration.ofSeconds(40))
                val began = System.nanoTime()
                core.close()
                val took = Duration.ofNanos(System.nanoTime() - began)
                val left = threadsOf(name)
                println(
                    "close() during a master lookup on a frozen cluster: lookup seen ${lookupSeen.toMillis()} ms after the " +
                        "freeze, close ${took.toMillis()} ms (shutdownTimeout ${shutdown.toMillis()} ms), threads left $left",
                )
                assertTrue(lookupSeen >= Duration.ZERO, "a thread of the core looked the master up again")
                assertTrue(took <= shutdown, "close() took ${took.toMillis()} ms, shutdownTimeout ${shutdown.toMillis()} ms")
                assertEquals(listOf<String>(), left, "threads of the core still running as close() returned")
            } finally {
                for (pid in pids) signal("CONT", pid)
                core.close()
            }
        }
    }

    /** How long until a thread of core [name] looks up the cluster's master (checked every 50 ms), or a negative duration. */
    private fun awaitLookup(name: String, timeout: Duration): Duration {
        val start = System.nanoTime()
        repeat((timeout.toMillis() / STEP_MS).toInt() + 1) {
            val looking = Thread.getAllStackTraces().any { (thread, stack) ->
                thread.name.startsWith("prime-$name-") && stack.any { it.className.endsWith("ClusterRoute") && it.methodName == "master" }
            }
            if (looking) return Duration.ofNanos(System.nanoTime() - start)
            if (System.nanoTime() - start > timeout.toNanos()) return Duration.ofMillis(-1)
            LockSupport.parkNanos(STEP_MS * 1_000_000)
        }
        return Duration.ofMillis(-1)
    }

    private fun threadsOf(name: String): List<String> =
        Thread.getAllStackTraces().keys.filter { it.isAlive && it.name.startsWith("prime-$name-") }.map { it.name }

    private fun signal(signal: String, pid: String) {
        val kill = ProcessBuilder("kill", "-$signal", pid).start()
        check(kill.waitFor(5, TimeUnit.SECONDS) && kill.exitValue() == 0) { "kill -$signal $pid failed" }
    }

    private companion object {
        const val STEP_MS = 50L
    }
}

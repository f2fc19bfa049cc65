package dev.prime.optimus

import dev.prime.CoreConfig
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration
import java.util.concurrent.ConcurrentHashMap
import java.util.concurrent.ConcurrentLinkedQueue
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicBoolean
import java.util.concurrent.atomic.AtomicInteger
import java.util.concurrent.atomic.AtomicLong
import kotlin.concurrent.thread

/**
 * A master of a real Redis Cluster (3 masters, 3 replicas, every node with an append-only file
 * synced on every write) is killed with SIGKILL while values stream through a topology on it, at
 * a moment its replica lacks some of its writes (the replication link was cut just before) and
 * values wait in the service's queue (its block is slower than the publisher):
 * the cluster promotes its replica on its own (automatic failover after `cluster-node-timeout`,
 * 1 s; no `CLUSTER FAILOVER`), the core finds the new master and goes on, and, with
 * [OptimusCore.Builder.replicaAcks] of 1, every value whose publish returned comes out of the
 * service, once. The killed node is started again afterwards (as a supervisor would), rejoins as
 * the new master's replica, and from then on the replica acknowledgements flow again.
 */
class ClusterFailoverTest {

    @Test
    fun aKilledMastersReplicaTakesOverAndNoAcceptedValueIsLost() {
        LocalRedisCluster.start(appendOnly = true).use { cluster ->
            val name = "failover"
            val slot = Keys(name).clusterSlot()
            val master = cluster.masterOf(slot)
            val replica = cluster.replicaOf(master)
            val config = CoreConfig.builder().name(name).sourceRetention(200_000).build()
            OptimusCore.builder().config(config).redis(cluster.url).replicaAcks(1)
                .publishTimeout(Duration.ofSeconds(PATIENCE_S)).build().use { core ->
                    val (source, reader) = slowDoubling(core, SERVICE_MILLIS)
                    core.start()

                    val accepted = ConcurrentHashMap<Int, Long>() // value -> when its publish returned
                    val startedAfterKill = ConcurrentHashMap<Int, Long>() // value -> when its publish, begun after the kill, returned
                    val refused = ConcurrentLinkedQueue<String>()
                    val seen = ConcurrentHashMap<Int, AtomicInteger>()
                    val firstSeenAfterKill = AtomicLong()
                    val killedAt = AtomicLong(Long.MAX_VALUE)
                    val stopPublishing = AtomicBoolean()
                    val stopReading = AtomicBoolean()
                    val beforeKill = CountDownLatch(BEFORE_KILL)
                    val afterRecovery = CountDownLatch(AFTER_RECOVERY)
                    val recovered = AtomicBoolean()

                    val publisher = thread(name = "failover-publisher") {
                        var value = 0
                        while (!stopPublishing.get() && value < MAX_VALUES) {
                            value++
                            val afterKill = System.nanoTime() > killedAt.get()
                            try {
                                core.publishAll(source, listOf(value))
                                accepted[value] = System.nanoTime()
                                if (afterKill) startedAfterKill[value] = accepted.getValue(value)
                                beforeKill.countDown()
                                if (recovered.get()) afterRecovery.countDown()
                            } catch (e: Exception) {
                                refused += "$value: $e"
                            }
                        }
                    }
                    val consumer = thread(name = "failover-reader") {
                        while (!stopReading.get()) {
                            val next = try {
                                reader.take(Duration.ofMillis(200))
                            } catch (_: Exception) {
                                continue // Redis unreachable for a moment: take again
                            }
                            next.ifPresent { doubledValue ->
                                val value = doubledValue / 2
                                seen.computeIfAbsent(value) { AtomicInteger() }.incrementAndGet()
                                if (startedAfterKill.containsKey(value)) firstSeenAfterKill.compareAndSet(0, System.nanoTime())
                            }
                        }
                    }
                    try {
                        assertTrue(beforeKill.await(PATIENCE_S, TimeUnit.SECONDS), "values flow before the kill")
                        // the worst moment: the replica lacks some of what the master acknowledged
                        val lag = cluster.cutReplicationLink(master, replica, Duration.ofMillis(300))
                        killedAt.set(System.nanoTime())
                        cluster.kill(master)
                        cluster.awaitMaster(slot, replica, Duration.ofSeconds(PATIENCE_S))
                        val promotedAt = System.nanoTime()
                        cluster.restart(master)
                        cluster.awaitReplica(master, replica, Duration.ofSeconds(PATIENCE_S))
                        val rejoinedAt = System.nanoTime()
                        recovered.set(true)
                        assertTrue(afterRecovery.await(PATIENCE_S, TimeUnit.SECONDS), "values flow after the failover")
                        stopPublishing.set(true)
                        publisher.join(TimeUnit.SECONDS.toMillis(PATIENCE_S))
                        assertTrue(!publisher.isAlive, "the publisher ended")

                        val deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(PATIENCE_S)
                        while (accepted.keys.any { !seen.containsKey(it) } && System.nanoTime() < deadline) Thread.sleep(20)
                        stopReading.set(true)
                        consumer.join(TimeUnit.SECONDS.toMillis(PATIENCE_S))

                        val lost = accepted.keys.filter { !seen.containsKey(it) }.sorted()
                        val duplicated = seen.filterValues { it.get() > 1 }.keys.sorted()
                        val firstAcceptedAfterKill = startedAfterKill.values.minOrNull()
                        println(
                            "cluster failover: ${accepted.size} values accepted, ${refused.size} refused, ${lost.size} lost, " +
                                "${duplicated.size} duplicated, ${seen.size - accepted.size} seen but not accepted; replica $lag bytes behind " +
                                "at the kill; " +
                                "replica promoted ${seconds(promotedAt - killedAt.get())} s after the kill, old master " +
                                "rejoined as replica after ${seconds(rejoinedAt - killedAt.get())} s; first publish begun after the kill accepted " +
                                "${firstAcceptedAfterKill?.let { seconds(it - killedAt.get()) }} s and first such value out " +
                                "${firstSeenAfterKill.get().takeIf { it != 0L }?.let { seconds(it - killedAt.get()) }} s after the kill",
                        )
                        assertEquals(emptyList<Int>(), lost, "accepted values lost in the failover")
                        assertEquals(emptyList<Int>(), duplicated, "values the reader got twice")
                        assertEquals(emptyList<String>(), refused.toList(), "publishes refused (Redis unreachable past the publish timeout)")
                        assertEquals(0, core.deadLetters("double").size, "dead letters")
                    } finally {
                        stopPublishing.set(true)
                        stopReading.set(true)
                        publisher.join(TimeUnit.SECONDS.toMillis(PATIENCE_S))
                        consumer.join(TimeUnit.SECONDS.toMillis(PATIENCE_S))
                    }
                }
        }
    }

    private fun seconds(nanos: Long) = "%.2f".format(nanos / 1e9)

    private companion object {
        const val PATIENCE_S = 60L
        const val BEFORE_KILL = 300
        const val AFTER_RECOVERY = 300
        const val MAX_VALUES = 1_000_000
        const val SERVICE_MILLIS = 3L
    }
}

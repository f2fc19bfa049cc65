package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.PrimeException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration

/**
 * [OptimusCore.Builder.replicaAcks]: on a Redis with no replica the core refuses to start at
 * once, saying why, instead of storing values a failover could lose; on a cluster master with a
 * replica every operation is confirmed and values flow.
 */
class ReplicaAcksTest {

    @Test
    fun aRedisWithoutTheReplicasAskedForIsRefusedAtBuild() {
        val started = System.nanoTime()
        val e = assertThrows(PrimeException::class.java) {
            OptimusCore.builder().redis(TestRedis.url).replicaAcks(1, Duration.ofMillis(200)).build().close()
        }
        assertTrue("0 of the 1 replicas" in e.message!!, e.message)
        assertTrue(System.nanoTime() - started < Duration.ofSeconds(10).toNanos(), "refused promptly")
    }

    @Test
    fun onAClusterMasterWithAReplicaEveryOperationIsConfirmed() {
        val config = CoreConfig.builder().name("acked").build()
        OptimusCore.builder().config(config).redis(TestCluster.url).replicaAcks(1).build().use { core ->
            val twice = core.chain("twice") { x: Int -> 2 * x }.toBlock()
            core.start()
            assertEquals((1..50).map { 2 * it }, (1..50).map { twice.process(it) })
        }
    }

    @Test
    fun badSettingsAreRefused() {
        assertThrows(IllegalArgumentException::class.java) { OptimusCore.builder().replicaAcks(-1) }
        assertThrows(IllegalArgumentException::class.java) { OptimusCore.builder().replicaAcks(1, Duration.ZERO) }
        assertThrows(IllegalArgumentException::class.java) { OptimusCore.builder().replicaAcks(1, Duration.ofSeconds(6)) }
    }
}

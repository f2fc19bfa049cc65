package dev.prime.optimus

import dev.prime.CoreConfig
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertNotEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.util.JedisClusterCRC16
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration

/**
 * On a Redis Cluster a crafted request whose reply key lies in another hash slot never reaches
 * a script's KEYS (a step with it would be refused whole, `CROSSSLOT`): the service refuses it
 * as outside the topology's reply namespace, dead-letters it with that reason and goes on
 * serving; nothing is written to the other slot.
 */
class ClusterPoisonEntryTest {

    @Test
    fun aRequestWithAReplyKeyInAnotherSlotIsDeadLetteredAndTheServiceKeepsServing() {
        val config = CoreConfig.builder().name("poison-slot").build()
        OptimusCore.builder().config(config).redis(TestCluster.url).callTimeout(Duration.ofSeconds(20)).build().use { core ->
            val echo = core.chain("echo") { x: Int -> x }.toBlock()
            core.start()
            val victim = "victim:list"
            assertNotEquals(core.keys.clusterSlot(), JedisClusterCRC16.getSlot(victim), "the victim is in another slot")
            val master = TestCluster.cluster.masterOf(core.keys.clusterSlot())
            master.jedis().use { raw ->
                raw.rpush(core.keys.serviceInput("echo"), Envelope.request(1L, victim.toByteArray(UTF_8), core.encode(7)))
            }
            assertEquals(5, echo.process(5), "the service still serves")
            val reasons = core.deadLetters("echo").map { it.reason }
            assertEquals(1, reasons.size, reasons.toString())
            assertTrue("outside this topology's reply namespace" in reasons[0], reasons[0])
            val victimMaster = TestCluster.cluster.masterOf(JedisClusterCRC16.getSlot(victim))
            victimMaster.jedis().use { assertFalse(it.exists(victim), "nothing was written to the other slot") }
        }
    }
}

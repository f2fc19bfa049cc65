package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import redis.clients.jedis.util.JedisClusterCRC16

/**
 * Every key a topology uses (what Keys makes, and the lists derived from them) is in one Redis
 * Cluster hash slot, the topology's: the atomic steps (scripts over many keys) need that on a
 * cluster, and different names give different slots, so topologies spread.
 */
class KeysSlotTest {

    @Test
    fun everyKeyOfATopologyIsInItsOneSlot() {
        for (name in listOf("robot", "robot-7", "a", "A.b_c-9", "x".repeat(64))) {
            val keys = Keys(name)
            val all = listOf(
                keys.serviceInput("svc"), keys.serviceProcessing("svc"), keys.deadLetters("svc"),
                keys.deadLettersTrimmed("svc"), keys.sourceLog("src"), keys.sourceReaders("src"), keys.sourceServices("src"),
                keys.reader("r1"), keys.processingOf(keys.reader("r1")), keys.missedOf(keys.reader("r1")),
                keys.processingOf(keys.serviceInput("svc")), keys.reply("instance:1"), keys.replyPrefix, keys.codec,
                keys.instances, keys.instanceLease("i"), keys.instanceLists("i"), keys.instanceDeclared("i"),
                keys.hostLease("svc"), keys.epoch,
                // names with braces and colons in the parts after the tag change nothing
                keys.serviceInput("{other}"), keys.sourceLog("}{"), keys.reader("{"),
            )
            val slots = all.map(JedisClusterCRC16::getSlot).toSet()
            assertEquals(setOf(keys.clusterSlot()), slots, "slots of the keys of '$name'")
        }
        val spread = (1..30).map { Keys("robot-$it").clusterSlot() }.toSet()
        assertEquals(30, spread.size, "30 robots' topologies in 30 slots")
    }
}

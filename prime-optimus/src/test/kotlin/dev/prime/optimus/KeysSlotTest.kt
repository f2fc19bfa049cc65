package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
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
            // every key Keys makes (found by reflection, so keys added later are checked too), and
            // the lists derived from a key; parts with braces after the tag change nothing
            val all = everyKey(keys, "svc") + everyKey(keys, "{other}") + everyKey(keys, "}{")
            assertTrue(all.size >= 40, "keys found: ${all.size}")
            val slots = all.map(JedisClusterCRC16::getSlot).toSet()
            assertEquals(setOf(keys.clusterSlot()), slots, "slots of the keys of '$name'")
        }
        val spread = (1..30).map { Keys("robot-$it").clusterSlot() }.toSet()
        assertEquals(30, spread.size, "30 robots' topologies in 30 slots")
    }

    /** What every method and property of [keys] that makes a key gives, with [part] for each name it takes. */
    private fun everyKey(keys: Keys, part: String): List<ByteArray> {
        val sample = keys.serviceInput(part)
        return Keys::class.java.declaredMethods
            .filter { it.returnType == ByteArray::class.java && !java.lang.reflect.Modifier.isStatic(it.modifiers) }
            .filter { method -> method.parameterTypes.all { it == String::class.java || it == ByteArray::class.java } }
            .filter { java.lang.reflect.Modifier.isPublic(it.modifiers) }
            .map { method ->
                val args = method.parameterTypes.map { if (it == String::class.java) part else sample }.toTypedArray()
                method.invoke(keys, *args) as ByteArray
            }
    }
}

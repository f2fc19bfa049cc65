package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNotEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration

/**
 * Topologies spread over a Redis Cluster's masters: two cores whose names hash to slots of
 * different masters each run their whole topology (a source, a linked service, a call, a
 * reader) on their own master, and no key of either is on the other's master.
 */
class ClusterPlacementTest {

    @Test
    fun twoTopologiesLandOnDifferentMastersAndEachKeepsAllItsKeysOnItsOwn() {
        val cluster = TestCluster.cluster
        val names = (1..100).map { "robot-$it" }
        val first = names.first()
        val firstMaster = cluster.masterOf(Keys(first).clusterSlot())
        val second = names.first { cluster.masterOf(Keys(it).clusterSlot()) !== firstMaster }
        val secondMaster = cluster.masterOf(Keys(second).clusterSlot())
        assertNotEquals(firstMaster.port, secondMaster.port)

        for ((name, factor) in listOf(first to 2, second to 3)) {
            core(name).use { core ->
                val numbers = EventBlock<Int>()
                val output = core.source("numbers", numbers).then(core.chain("times") { x: Int -> x * factor })
                val reader = output.reader()
                val call = core.chain("plus-one") { x: Int -> x + 1 }.toBlock()
                core.start()
                (1..20).forEach(numbers::publish)
                val seen = (1..20).map { reader.take(Duration.ofSeconds(10)).orElseThrow { AssertionError("value $it of $name") } }
                assertEquals((1..20).map { it * factor }, seen, name)
                assertEquals(42, call.process(41), name)
                val (own, other) = if (name == first) firstMaster to secondMaster else secondMaster to firstMaster
                assertTrue(keysOf(own, name).isNotEmpty(), "the keys of '$name' are on its master $own")
                assertEquals(emptyList<String>(), keysOf(other, name), "no key of '$name' on the other master $other")
            }
        }
    }

    private fun core(name: String) =
        OptimusCore.builder().config(CoreConfig.builder().name(name).build()).redis(TestCluster.url).build()

    private fun keysOf(node: LocalRedisCluster.Node, topology: String): List<String> =
        node.jedis().use { TestRedis.keysOf(it, topology) }
}

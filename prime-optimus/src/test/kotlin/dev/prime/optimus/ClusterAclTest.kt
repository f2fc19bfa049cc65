package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.PrimeException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Protocol
import java.time.Duration

/**
 * Logging in to a Redis Cluster: a user with exactly the permissions docs/architecture.md lists
 * for a cluster (its topology's key pattern, the commands, `cluster|slots`, `wait`) runs a
 * topology with replica acknowledgements; a wrong password is refused at once, saying so,
 * without showing the password.
 */
class ClusterAclTest {

    @Test
    fun theDocumentedPermissionsAreEnoughAndAWrongPasswordIsRefused() {
        val user = "prime-cluster-robot"
        val nodes = TestCluster.cluster.nodes
        for (node in nodes) {
            node.jedis().use { admin ->
                admin.sendCommand(Protocol.Command.ACL, *(listOf("SETUSER", user, "reset", "on", ">s3cret", "~prime:{acl-robot}:*") + PERMISSIONS).toTypedArray())
            }
        }
        try {
            val url = TestCluster.url.replace("redis-cluster://", "redis-cluster://$user:s3cret@")
            val config = CoreConfig.builder().name("acl-robot").build()
            OptimusCore.builder().config(config).redis(url).replicaAcks(1).build().use { core ->
                val numbers = EventBlock<Int>()
                val reader = core.source("numbers", numbers).then(core.chain("inc") { x: Int -> x + 1 }).reader()
                val square = core.chain("square") { x: Int -> x * x }.toBlock()
                core.start()
                (1..10).forEach(numbers::publish)
                assertEquals((2..11).toList(), (1..10).map { reader.take(Duration.ofSeconds(10)).orElseThrow() })
                assertEquals(49, square.process(7))
            }

            val wrong = TestCluster.url.replace("redis-cluster://", "redis-cluster://$user:wrong-pw@")
            val started = System.nanoTime()
            val refused = assertThrows(PrimeException::class.java) { OptimusCore.builder().config(config).redis(wrong).build().close() }
            assertTrue(System.nanoTime() - started < Duration.ofSeconds(10).toNanos(), "refused promptly")
            val message = refused.message!!
            assertTrue("WRONGPASS" in message || "invalid username-password" in message, message)
            assertFalse("wrong-pw" in message, message)
        } finally {
            for (node in nodes) node.jedis().use { it.sendCommand(Protocol.Command.ACL, "DELUSER", user) }
        }
    }

    private companion object {
        /** docs/architecture.md, "Redis permissions": the commands, and on a cluster `cluster|slots` and `wait`. */
        val PERMISSIONS = (
            "+blmove +client|setname +del +eval +evalsha +exec +exists +get +hdel +hello +hgetall +hlen +hset +incr " +
                "+incrby +info +lindex +llen +lmove +lpop +lrange +lrem +lset +ltrim +multi +pexpire +ping +pttl +rpush +sadd +scard " +
                "+set +sismember +smembers +srem +type +unwatch +watch +cluster|slots +wait"
            ).split(' ')
    }
}

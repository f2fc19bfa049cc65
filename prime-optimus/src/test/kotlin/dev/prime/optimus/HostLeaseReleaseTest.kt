package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration

/**
 * What a closing core releases of its host leases ([HostLeases.releaseAll]): every lease it holds in
 * Redis, also one a standby's claim won while the core closed (granted by Redis, not yet recorded
 * as held), and never a lease another instance holds.
 */
class HostLeaseReleaseTest {

    @Test
    fun aLeaseGrantedToAStandbyButNotYetRecordedAsHeldIsReleasedByClose() {
        val keys = Keys("lease-release-standby")
        val connections = RedisConnections(RedisTarget.parse(TestRedis.url, keys), "lease-release-standby")
        val leases = HostLeases(keys, connections, "instance-a", LEASE) { false }
        Jedis(URI(TestRedis.url)).use { jedis ->
            jedis.del(keys.hostLease("svc"))
            assertEquals(emptyMap<String, Long>(), leases.tryClaim(jedis, listOf("svc")), "the lease was free: claimed")
            // the race: close() snapshots the held leases before the standby's thread records its grant
            leases.drop("svc")
            val pipeline = jedis.pipelined()
            leases.releaseAll(pipeline)
            pipeline.sync()
            assertNull(jedis.get(keys.hostLease("svc")), "released at close, not left to lapse ${LEASE.toMillis()} ms later")
        }
        connections.closeAll()
    }

    @Test
    fun closeLeavesALeaseAnotherInstanceHoldsAlone() {
        val keys = Keys("lease-release-other")
        val connections = RedisConnections(RedisTarget.parse(TestRedis.url, keys), "lease-release-other")
        val standby = HostLeases(keys, connections, "instance-b", LEASE) { false }
        Jedis(URI(TestRedis.url)).use { jedis ->
            jedis.set(keys.hostLease("svc"), "instance-a".toByteArray(UTF_8))
            jedis.pexpire(keys.hostLease("svc"), LEASE.toMillis())
            val refused = standby.tryClaim(jedis, listOf("svc"))
            assertEquals(setOf("svc"), refused.keys, "instance-a holds it: the standby waits")
            val pipeline = jedis.pipelined()
            standby.releaseAll(pipeline)
            pipeline.sync()
            assertEquals("instance-a", jedis.get(keys.hostLease("svc"))?.toString(UTF_8))
        }
        connections.closeAll()
    }

    private companion object {
        val LEASE: Duration = Duration.ofSeconds(30)
    }
}

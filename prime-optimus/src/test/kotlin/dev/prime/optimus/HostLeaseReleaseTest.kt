package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration
import java.util.concurrent.CountDownLatch
import java.util.concurrent.Executors
import java.util.concurrent.TimeUnit.SECONDS

/**
 * What a closing core releases of its host leases ([HostLeases.releaseAll]): every lease it holds in
 * Redis, also one a standby's claim won while the core closed (granted by Redis, not yet recorded
 * as held), and never a lease another instance holds; and what a failed declaration releases
 * ([HostLeases.release]) stays released though a renewal was in flight.
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

    @Test
    fun aLeaseReleasedWhileARenewalIsInFlightIsNotWrittenAgainByIt() {
        val keys = Keys("lease-release-renewal")
        val connections = RedisConnections(RedisTarget.parse(TestRedis.url, keys), "lease-release-renewal")
        // { false }: a combinator's or timer's lease, which the heartbeat claims again when it finds it gone
        val leases = HostLeases(keys, connections, "instance-a", LEASE) { false }
        val threads = Executors.newFixedThreadPool(2)
        try {
            Jedis(URI(TestRedis.url)).use { jedis ->
                jedis.del(keys.hostLease("svc"))
                leases.claim(listOf("svc"), "lease-release-renewal")
                assertEquals("instance-a", jedis.get(keys.hostLease("svc"))?.toString(UTF_8), "claimed")
                val renewing = CountDownLatch(1)
                val proceed = CountDownLatch(1)
                leases.beforeRenewScript = {
                    renewing.countDown()
                    assertTrue(proceed.await(10, SECONDS), "the renewal was let go on")
                }
                leases.releaseWaitsForRenewal = { proceed.countDown() }
                val renewal = threads.submit<Map<String, String>> { Jedis(URI(TestRedis.url)).use(leases::renew) }
                assertTrue(renewing.await(10, SECONDS), "the heartbeat's renewal took its snapshot of the held leases")
                // the declaration that claimed it failed: its undo releases the lease while the renewal is in flight
                val release = threads.submit { leases.release(listOf("svc")) }
                release.get(10, SECONDS)
                proceed.countDown()
                assertEquals(emptyMap<String, String>(), renewal.get(10, SECONDS))
                assertNull(
                    jedis.get(keys.hostLease("svc"))?.toString(UTF_8),
                    "the released lease stays released; a renewal in flight wrote it again, for ${jedis.pttl(keys.hostLease("svc"))} ms",
                )
                assertEquals(emptySet<String>(), leases.services, "no longer held")
                assertEquals(emptyMap<String, String>(), leases.renew(jedis), "the next renewal does not name it")
                assertNull(jedis.get(keys.hostLease("svc")), "nor claims it again")
            }
        } finally {
            threads.shutdownNow()
            connections.closeAll()
        }
    }

    private companion object {
        val LEASE: Duration = Duration.ofSeconds(30)
    }
}

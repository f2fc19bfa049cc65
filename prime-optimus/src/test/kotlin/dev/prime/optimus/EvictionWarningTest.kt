package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.conformance.CapturedStderr
import org.junit.jupiter.api.AfterAll
import org.junit.jupiter.api.AfterEach
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.BeforeAll
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import redis.clients.jedis.Protocol
import java.net.ServerSocket
import java.net.URI
import java.nio.file.Files
import java.nio.file.Path
import java.time.Duration

/**
 * A Redis that may evict keys at its `maxmemory` (a `maxmemory-policy` other than `noeviction`)
 * gets one WARN per core at [OptimusCore.start], naming the policy, the `maxmemory`, what it may
 * delete and the fix; a Redis that evicts nothing gets none. The settings are changed with
 * `CONFIG SET` on a Redis of this class's own (restored after each test), and on a Redis Cluster
 * of its own for the check on the master of the topology's slot.
 */
class EvictionWarningTest {

    @AfterEach
    fun restoreTheSettings() {
        admin().use { admin ->
            admin.configSet("maxmemory", "0")
            admin.configSet("maxmemory-policy", "noeviction")
        }
    }

    @Test
    fun allKeysLruWarnsOnceThatQueuesAndValuesInFlightMayBeLost() {
        configure("1gb", "allkeys-lru")
        val warnings = warningsOfStarting("evict-allkeys", redis.uri)
        assertEquals(1, warnings.size, "eviction WARN lines: $warnings")
        val line = warnings.single()
        assertTrue("maxmemory-policy is allkeys-lru with maxmemory 1073741824 bytes" in line, line)
        assertTrue("any key of the topology" in line && "values in flight" in line, line)
        assertTrue("CONFIG SET maxmemory-policy noeviction" in line, line)
    }

    @Test
    fun volatileLruWarnsOnceThatTheLeasesMayBeDeleted() {
        configure("1gb", "volatile-lru")
        val warnings = warningsOfStarting("evict-volatile", redis.uri)
        assertEquals(1, warnings.size, "eviction WARN lines: $warnings")
        val line = warnings.single()
        assertTrue("maxmemory-policy is volatile-lru" in line, line)
        assertTrue("the keys that have an expiry, which are the leases" in line && "taken for dead" in line, line)
        assertTrue("CONFIG SET maxmemory-policy noeviction" in line, line)
    }

    @Test
    fun theCheckWarnsThroughASlowLinkToo() {
        configure("1gb", "allkeys-lru")
        val warnings = warningsOfStarting("evict-slow", FaultProxy.slowLinkTo(redis.uri))
        assertEquals(1, warnings.size, "eviction WARN lines: $warnings")
        assertTrue("maxmemory-policy is allkeys-lru" in warnings.single(), warnings.single())
    }

    @Test
    fun noEvictionWithAMaxmemoryGivesNoWarning() {
        configure("1gb", "noeviction")
        assertEquals(emptyList<String>(), warningsOfStarting("evict-none", redis.uri))
    }

    @Test
    fun anEvictionPolicyWithoutAMaxmemoryGivesNoWarning() {
        configure("0", "allkeys-lru")
        assertEquals(emptyList<String>(), warningsOfStarting("evict-unbounded", redis.uri))
    }

    /**
     * A Redis user with the documented permissions but `info` is refused the check (ACL LOG shows
     * it asked): the core starts and answers calls as before, without an eviction WARN.
     */
    @Test
    fun aUserWithoutInfoSkipsTheCheckAndNothingElseChanges() {
        configure("1gb", "allkeys-lru")
        val example = Files.readAllLines(Path.of("..", "docs", "architecture.md")).single { it.startsWith("ACL SETUSER robot ") }
        val commands = example.split(" ").filter { it.startsWith("+") && it != "+info" }
        val user = "prime-noinfo"
        admin().use { admin ->
            admin.sendCommand(Protocol.Command.ACL, "SETUSER", user, "reset", "on", ">secret", "~prime:{evict-noinfo}:*", *commands.toTypedArray())
            admin.aclLogReset()
        }
        try {
            val url = redis.uri.replace("redis://", "redis://$user:secret@")
            val warnings = warningsOfStarting("evict-noinfo", url) { core ->
                val twice = core.chain("twice") { x: Int -> 2 * x }.toBlock()
                core.start()
                assertEquals((1..5).map { 2 * it }, (1..5).map { twice.process(it) })
            }
            assertEquals(emptyList<String>(), warnings)
            val refused = admin().use { admin -> admin.aclLog().filter { it.username == user }.map { "${it.reason} ${it.`object`}" } }
            assertEquals(listOf("command info"), refused, "what Redis refused the user without info (ACL LOG)")
        } finally {
            admin().use { it.sendCommand(Protocol.Command.ACL, "DELUSER", user) }
        }
    }

    /** A Redis out of reach when the check runs ends it after one attempt, without an exception or a WARN. */
    @Test
    fun aRedisOutOfReachEndsTheCheckQuietly() {
        val port = ServerSocket(0, 1, java.net.InetAddress.getLoopbackAddress()).use { it.localPort } // nothing listens there now
        val connections = RedisConnections(RedisEndpoint.parse("redis://127.0.0.1:$port"), "evict-unreachable")
        try {
            CapturedStderr().use { err ->
                val started = System.nanoTime()
                RedisSession(connections).use { session -> EvictionCheck.check(session, "evict-unreachable") }
                val took = Duration.ofNanos(System.nanoTime() - started)
                assertTrue(took < RedisConnections.COMMAND_TIMEOUT, "the check took $took")
                assertEquals(emptyList<String>(), err.lines().filter { "evict-unreachable" in it && " WARN " in it })
            }
        } finally {
            connections.closeAll()
        }
    }

    /**
     * On a Redis Cluster the settings that count are those of the master holding the topology's
     * slot: the WARN names its policy, not the other master's.
     */
    @Test
    fun onARedisClusterTheMasterOfTheTopologysSlotIsChecked() {
        LocalRedisCluster.start(masters = 2).use { cluster ->
            val name = "evict-cluster"
            val master = cluster.masterOf(Keys(name).clusterSlot())
            for (node in cluster.nodes) {
                node.jedis().use { jedis ->
                    jedis.configSet("maxmemory", "1gb")
                    jedis.configSet("maxmemory-policy", if (node === master) "volatile-lfu" else "allkeys-random")
                }
            }
            val warnings = warningsOfStarting(name, cluster.url)
            assertEquals(1, warnings.size, "eviction WARN lines: $warnings")
            assertTrue("maxmemory-policy is volatile-lfu" in warnings.single(), warnings.single())

            // a read: with replica acknowledgements it is not followed by a WAIT (one round trip)
            val connections = RedisConnections(RedisTarget.parse(cluster.url, Keys(name)), name, ReplicaAcks(1, Duration.ofSeconds(1)))
            try {
                RedisSession(connections).use { session ->
                    session.once { it.ping() } // connected, to the master of the slot
                    val before = master.jedis().use { waits(it) }
                    EvictionCheck.check(session, name)
                    assertEquals(before, master.jedis().use { waits(it) }, "WAIT commands the master ran for the check")
                }
            } finally {
                connections.closeAll()
            }
        }
    }

    /** How many `WAIT` commands the server [jedis] talks to ran, from its `INFO commandstats`. */
    private fun waits(jedis: Jedis): Long =
        jedis.info("commandstats").lines().firstOrNull { it.startsWith("cmdstat_wait:") }
            ?.substringAfter("calls=")?.substringBefore(',')?.toLong() ?: 0L

    /** Sets the Redis of this class to [maxmemory] and [policy]. */
    private fun configure(maxmemory: String, policy: String) {
        admin().use { admin ->
            admin.configSet("maxmemory", maxmemory)
            admin.configSet("maxmemory-policy", policy)
        }
    }

    /**
     * The eviction WARN lines (of [EvictionCheck]) that name core [name] while a core of that name
     * on [url] is declared and started by [run] (by default: started) and closed.
     */
    private fun warningsOfStarting(name: String, url: String, run: (OptimusCore) -> Unit = { it.start() }): List<String> =
        CapturedStderr().use { err ->
            OptimusCore.builder().config(CoreConfig.builder().name(name).build()).redis(url).build().use(run)
            err.lines().filter { " WARN " in it && "core '$name'" in it && "may evict keys" in it }
        }

    private fun admin(): Jedis = Jedis(URI(redis.uri))

    private companion object {
        lateinit var redis: EmbeddedRedis

        @JvmStatic
        @BeforeAll
        fun startRedis() {
            redis = EmbeddedRedis.start()
        }

        @JvmStatic
        @AfterAll
        fun stopRedis() {
            redis.close()
        }
    }
}

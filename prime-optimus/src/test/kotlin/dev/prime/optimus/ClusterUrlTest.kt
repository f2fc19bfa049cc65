package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.HostAndPort

/** `redis-cluster://` URLs: seeds, login, TLS; bad ones say what is wrong and never show the password. */
class ClusterUrlTest {

    @Test
    fun readsTheSeedsLoginAndTls() {
        val full = RedisClusterEndpoint.parse("rediss-cluster://robot:s%40cret@node-1.example:7000,[::1]:7001,10.0.0.3")
        assertEquals(listOf(HostAndPort("node-1.example", 7000), HostAndPort("::1", 7001), HostAndPort("10.0.0.3", 6379)), full.seeds)
        assertEquals("robot", full.user)
        assertEquals("s@cret", full.password)
        assertTrue(full.tls)
        assertEquals("rediss-cluster://robot:***@node-1.example:7000,[::1]:7001,10.0.0.3:6379", full.toString())

        val plain = RedisClusterEndpoint.parse("redis-cluster://127.0.0.1:7000/0")
        assertNull(plain.user)
        assertFalse(plain.tls)
        assertTrue(RedisClusterEndpoint.isClusterUrl("REDIS-CLUSTER://h:1"))
        assertFalse(RedisClusterEndpoint.isClusterUrl("redis://h:1"))
    }

    @Test
    fun badClusterUrlsSayWhatIsWrongWithoutShowingThePassword() {
        val cases = mapOf(
            "redis-cluster://u:topsecret@h:7000/1" to "database 0 only",
            "redis-cluster://u:topsecret@h:7000,,h:7001" to "empty node",
            "redis-cluster://u:topsecret@h:99999" to "port",
            "redis-cluster://u:topsecret@h:7000?x=1" to "query",
            "redis-cluster://u:topsecret@" to "empty node",
            "redis-cluster://u:topsecret@:7000" to "no host",
        )
        for ((url, expected) in cases) {
            val e = assertThrows(IllegalArgumentException::class.java, { OptimusCore.builder().redis(url) }, url)
            assertTrue(e.message!!.contains(expected), "$url: ${e.message}")
            assertFalse(e.message!!.contains("topsecret"), "$url: ${e.message}")
        }
    }
}

package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

class RedisEndpointTest {

    @Test
    fun readsEveryPartOfAUrl() {
        val full = RedisEndpoint.parse("rediss://robot:s%40cret@redis.example.com:6380/3")
        assertEquals("redis.example.com", full.host)
        assertEquals(6380, full.port)
        assertEquals("robot", full.user)
        assertEquals(3, full.database)
        assertTrue(full.tls)
        assertEquals("rediss://robot:***@redis.example.com:6380/3", full.toString())

        val plain = RedisEndpoint.parse("redis://localhost")
        assertEquals(6379, plain.port)
        assertEquals(0, plain.database)
        assertNull(plain.user)
        assertFalse(plain.tls)

        val passwordOnly = RedisEndpoint.parse("redis://:pw@10.0.0.5:7000")
        assertNull(passwordOnly.user)
        assertEquals("redis://:***@10.0.0.5:7000/0", passwordOnly.toString())
    }

    @Test
    fun badUrlsSayWhatIsWrongWithoutShowingThePassword() {
        val cases = mapOf(
            "http://localhost:6379" to "scheme",
            "redis://:secret@/0" to "no host",
            "redis://localhost/db1" to "database",
            "redis://localhost:6379/0?timeout=1" to "query",
            "redis://user:secret@local host" to "invalid",
        )
        for ((url, words) in cases) {
            val e = assertThrows(IllegalArgumentException::class.java, { RedisEndpoint.parse(url) }, url)
            assertTrue(e.message!!.contains(words), "$url: ${e.message}")
            assertFalse(e.message!!.contains("secret"), "$url: ${e.message}")
        }
        val e = assertThrows(IllegalArgumentException::class.java) { OptimusCore.builder().redis("localhost:6379") }
        assertTrue(e.message!!.contains("redis://"), e.message)
    }
}

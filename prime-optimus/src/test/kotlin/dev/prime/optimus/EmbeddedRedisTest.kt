package dev.prime.optimus

import dev.prime.PrimeException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import redis.clients.jedis.Jedis
import java.net.URI
import java.nio.file.Files
import java.nio.file.Path
import java.time.Duration

class EmbeddedRedisTest {

    @Test
    fun startsARealServerAndStopsIt() {
        val redis = EmbeddedRedis.start()
        redis.use {
            assertTrue(it.isRunning)
            Jedis(URI(it.uri)).use { jedis ->
                jedis.set("k", "v")
                assertEquals("v", jedis.get("k"))
                val version = Regex("redis_version:(\\d+)\\.(\\d+)").find(jedis.info("server"))!!.groupValues
                assertTrue(version[1].toInt() > 6 || (version[1].toInt() == 6 && version[2].toInt() >= 2), version[0])
            }
        }
        assertFalse(redis.isRunning)
        assertFalse(runCatching { Jedis(URI(redis.uri)).use { it.ping() } }.isSuccess, "stopped")
        redis.close() // idempotent
    }

    @Test
    fun appendOnlyDirKeepsDataAcrossACrash(@TempDir dir: Path) {
        EmbeddedRedis.builder().appendOnlyDir(dir).start().use { redis ->
            Jedis(URI(redis.uri)).use { it.rpush("list", "a", "b") }
            redis.kill()
            assertFalse(redis.isRunning)
            redis.restart()
            Jedis(URI(redis.uri)).use { assertEquals(listOf("a", "b"), it.lrange("list", 0, -1)) }
        }
        assertTrue(Files.exists(dir), "a directory given by the user is kept")
    }

    @Test
    fun aTakenPortFailsWithTheServersOwnWords() {
        EmbeddedRedis.start().use { first ->
            val e = assertThrows(PrimeException::class.java) { EmbeddedRedis.builder().port(first.port).start() }
            assertTrue(e.message!!.contains("port ${first.port}"), e.message)
        }
    }

    @Test
    fun badSettingsAreRefused() {
        assertThrows(IllegalArgumentException::class.java) { EmbeddedRedis.builder().port(0) }
        assertThrows(IllegalArgumentException::class.java) { EmbeddedRedis.builder().port(70000) }
        assertThrows(IllegalArgumentException::class.java) { EmbeddedRedis.builder().executable(Path.of("/no/such/redis")) }
        assertThrows(IllegalArgumentException::class.java) { EmbeddedRedis.builder().startTimeout(Duration.ZERO) }
        assertThrows(IllegalArgumentException::class.java) { EmbeddedRedis.builder().startTimeout(Duration.ofSeconds(-1)) }
    }

    @Test
    fun theServerListensOnTheLoopbackAddressOnly() {
        EmbeddedRedis.start().use { redis ->
            val bind = Jedis(URI(redis.uri)).use { it.configGet("bind") }
            assertEquals(mapOf("bind" to "127.0.0.1"), bind, "the embedded server binds 127.0.0.1 only")
        }
    }

    @Test
    fun closeDeletesTheServersOwnFilesAndIsIdempotent() {
        val redis = EmbeddedRedis.start()
        val dir = Jedis(URI(redis.uri)).use { Path.of(it.configGet("dir").getValue("dir")) }
        assertTrue(Files.isDirectory(dir), "the server works in $dir")
        redis.close()
        redis.close()
        assertFalse(redis.isRunning)
        assertFalse(Files.exists(dir), "close() deletes the files of a server that was not asked to persist: $dir")
    }
}

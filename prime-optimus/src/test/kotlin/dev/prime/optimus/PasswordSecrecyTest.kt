package dev.prime.optimus

import dev.prime.conformance.CapturedStderr
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.io.PrintWriter
import java.io.StringWriter
import java.net.ServerSocket
import java.net.URI

/** No message, cause or toString ever shows a Redis password, whatever characters it holds. */
class PasswordSecrecyTest {

    @Test
    fun passwordsWithAwkwardCharactersAreReadAndNeverShown() {
        val cases = mapOf(
            "redis://robot:Pw%zz9Secret@127.0.0.1:6379" to "Pw%zz9Secret", // '%' not followed by two hex digits
            "redis://robot:Pw%25Secret@127.0.0.1:6379" to "Pw%Secret",
            "redis://robot:Pw Secret@127.0.0.1:6379" to "Pw Secret",
            "redis://robot:Pw/Secret@127.0.0.1:6379/2" to "Pw/Secret",
            "redis://robot:Pw@Secret@127.0.0.1:6379" to "Pw@Secret",
            "redis://:Pw/Sec ret%@[::1]:6380" to "Pw/Sec ret%",
        )
        for ((url, password) in cases) {
            val endpoint = RedisEndpoint.parse(url)
            assertEquals(password, endpoint.password, url)
            assertEquals(endpoint.toString().contains("***"), true, endpoint.toString())
            assertNoSecret(endpoint.toString(), "Secret", url)
        }
    }

    @Test
    fun badUrlsWithAwkwardPasswordsNeverShowThem() {
        val urls = listOf(
            "redis://robot:Pw%zzSecret@127.0.0.1:notaport",
            "redis://robot:Pw Secret@127.0.0.1:6379/db",
            "redis://robot:Pw/Secret@127.0.0.1:6379/0?x=1",
            "redis://robot:Pw/Secret@",
            "redis://robot:Pw/Secret@bad host:6379",
            "redis://robot:Pw/Secret@127.0.0.1:99999",
            "http://robot:Pw/Secret@127.0.0.1:6379",
            "robot:Pw%Secret@127.0.0.1:6379",
        )
        for (url in urls) {
            val e = assertThrows(IllegalArgumentException::class.java, { RedisEndpoint.parse(url) }, url)
            assertNoSecret(e, "Secret", url)
            val viaBuilder = assertThrows(IllegalArgumentException::class.java, { OptimusCore.builder().redis(url) }, url)
            assertNoSecret(viaBuilder, "Secret", url)
        }
    }

    @Test
    fun connectionFailuresNeverShowThePassword() {
        val closedPort = ServerSocket(0).use { it.localPort }
        val refused = assertThrows(Exception::class.java) {
            OptimusCore.builder().redis("redis://robot:Pw/Secret1@127.0.0.1:$closedPort").build().close()
        }
        assertNoSecret(refused, "Secret1", "connection refused")

        EmbeddedRedis.start().use { redis ->
            Jedis(URI(redis.uri)).use { it.configSet("requirepass", "Right%Secret2") }
            val wrong = assertThrows(Exception::class.java) {
                OptimusCore.builder().redis("redis://:Wrong%25Secret3@127.0.0.1:${redis.port}").build().close()
            }
            assertNoSecret(wrong, "Secret3", "wrong password")
            OptimusCore.builder().redis("redis://:Right%25Secret2@127.0.0.1:${redis.port}").build().use { core ->
                val call = core.chain("echo") { x: Int -> x }.toBlock()
                core.start()
                assertEquals(3, call.process(3), "the right password logs in")
                assertNoSecret(core.redisUrl + core.toString(), "Secret2", "core")
            }
        }
    }

    @Test
    fun theStartLineNamesTheRedisWithoutItsPassword() {
        EmbeddedRedis.start().use { redis ->
            Jedis(URI(redis.uri)).use { it.configSet("requirepass", "Start%Secret4") }
            val lines = CapturedStderr().use { err ->
                OptimusCore.builder().config(dev.prime.CoreConfig.builder().name("start-line").build()).redis("redis://:Start%25Secret4@127.0.0.1:${redis.port}").build()
                    .use { core ->
                        core.chain("echo") { x: Int -> x }
                        core.start()
                    }
                err.lines().filter { it.contains("core 'start-line' started on ") }
            }
            assertEquals(1, lines.size, lines.toString())
            val line = lines[0]
            assertTrue(line.contains(" INFO "), line)
            assertTrue(line.contains("started on optimus with Redis redis://:***@127.0.0.1:${redis.port}"), line)
            assertTrue(line.contains("hosting services [echo]"), line)
            assertNoSecret(line, "Secret4", "start line")
        }
    }

    private fun assertNoSecret(e: Throwable, secret: String, case: String) {
        val trace = StringWriter().also { e.printStackTrace(PrintWriter(it)) }.toString()
        assertNoSecret(trace, secret, case)
    }

    private fun assertNoSecret(text: String, secret: String, case: String) {
        assertFalse(text.contains(secret), "$case shows the password: $text")
    }
}

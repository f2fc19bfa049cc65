package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.io.File
import java.nio.file.Files
import java.nio.file.Path
import java.util.concurrent.CompletableFuture
import java.util.concurrent.ConcurrentLinkedQueue
import java.util.concurrent.TimeUnit
import java.util.concurrent.TimeoutException

/**
 * An embedded Redis whose core is never closed stops with its JVM, as [EmbeddedRedis] documents:
 * on a normal exit and on SIGTERM the server process ends and its files are deleted.
 */
class EmbeddedRedisShutdownHookTest {

    @Test
    fun aNeverClosedCoresRedisStopsWhenItsJvmReturnsFromMain() {
        assertStopsWithItsJvm(exits = true) { it.outputStream.use { input -> input.write("exit\n".toByteArray()) } }
    }

    @Test
    fun aNeverClosedCoresRedisStopsWhenItsJvmIsSentSigterm() {
        assertStopsWithItsJvm(exits = false) { it.destroy() } // SIGTERM
    }

    private fun assertStopsWithItsJvm(exits: Boolean, signal: (Process) -> Unit) {
        val java = File(System.getProperty("java.home"), "bin/java").path
        val jvm = ProcessBuilder(java, "-Xmx128m", "-cp", System.getProperty("java.class.path"), AbandonedRedisMain::class.java.name)
            .redirectErrorStream(true)
            .start()
        var redis: ProcessHandle? = null
        try {
            val lines = ConcurrentLinkedQueue<String>()
            val ready = CompletableFuture.supplyAsync {
                jvm.inputStream.bufferedReader().lineSequence().onEach { lines += it }.firstOrNull { it.startsWith("READY ") }
            }
            val line = try {
                ready.get(60, TimeUnit.SECONDS) // the finally's kill ends the read if this times out
            } catch (e: TimeoutException) {
                null
            } ?: throw AssertionError("no READY line within 60 s; output:\n${lines.joinToString("\n")}")
            val words = line.split(" ")
            redis = ProcessHandle.of(words[1].toLong()).orElseThrow { AssertionError("no redis-server with pid ${words[1]}") }
            val dir = Path.of(words[2])
            assertTrue(redis.isAlive && Files.isDirectory(dir), "the child's Redis runs in $dir")

            signal(jvm)
            assertTrue(jvm.waitFor(30, TimeUnit.SECONDS), "the child JVM ended within 30 s")
            if (exits) assertEquals(0, jvm.exitValue(), "main returned normally")
            try {
                redis.onExit().get(10, TimeUnit.SECONDS)
            } catch (e: TimeoutException) {
                throw AssertionError("redis-server ${redis.pid()} still runs 10 s after its JVM ended", e)
            }
            assertFalse(Files.exists(dir), "the hook deleted the server's files: $dir")
        } finally {
            jvm.destroyForcibly()
            redis?.destroyForcibly()
        }
    }
}

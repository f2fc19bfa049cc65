package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Assumptions.assumeTrue
import org.junit.jupiter.api.Test
import java.io.File
import java.nio.file.Files
import java.nio.file.Path
import java.util.concurrent.CompletableFuture
import java.util.concurrent.ConcurrentLinkedQueue
import java.util.concurrent.TimeUnit
import java.util.concurrent.TimeoutException

/**
 * An embedded Redis whose core is never closed does not outlive its JVM, as [EmbeddedRedis]
 * documents: on a normal exit, on SIGTERM (the shutdown hook) and on SIGKILL (the watchdog shell)
 * the server process ends and its files are deleted; the files of a server that crashed before
 * its JVM ended are deleted too.
 */
class EmbeddedRedisJvmEndTest {

    @Test
    fun aNeverClosedCoresRedisStopsWhenItsJvmReturnsFromMain() {
        assertStopsWithItsJvm("exit", exitCode = 0) { it.outputStream.use { input -> input.write("exit\n".toByteArray()) } }
    }

    @Test
    fun aCrashedServersFilesAreDeletedWhenItsJvmReturnsFromMain() {
        assertStopsWithItsJvm("crashed", exitCode = 0) { it.outputStream.use { input -> input.write("exit\n".toByteArray()) } }
    }

    @Test
    fun aNeverClosedCoresRedisStopsWhenItsJvmIsSentSigterm() {
        assertStopsWithItsJvm("wait", exitCode = 143) { it.destroy() } // SIGTERM
    }

    @Test
    fun aNeverClosedCoresRedisStopsWhenItsJvmIsKilled() {
        assumeTrue(Files.isExecutable(Path.of("/bin/sh")), "the watchdog needs /bin/sh")
        assertStopsWithItsJvm("wait", exitCode = 137) { it.destroyForcibly() } // SIGKILL: no hook runs
    }

    /** Runs [AbandonedRedisMain] in [childMode], ends it with [end], and checks that its server and files are gone. */
    private fun assertStopsWithItsJvm(childMode: String, exitCode: Int, end: (Process) -> Unit) {
        val java = File(System.getProperty("java.home"), "bin/java").path
        val jvm = ProcessBuilder(java, "-Xmx128m", "-cp", System.getProperty("java.class.path"), AbandonedRedisMain::class.java.name, childMode)
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
            val dir = Path.of(words[2])
            assertTrue(Files.isDirectory(dir), "the child's Redis has its files in $dir")
            // a crashed server is gone already (its JVM collected it): only its files are left to check
            val server = ProcessHandle.of(words[1].toLong()).orElse(null)
            if (childMode != "crashed") assertTrue(server?.isAlive == true, "the child's redis-server ${words[1]} runs")
            redis = server

            end(jvm)
            assertTrue(jvm.waitFor(30, TimeUnit.SECONDS), "the child JVM ended within 30 s")
            assertEquals(exitCode, jvm.exitValue(), "how the JVM ended")
            // redis-server is not this JVM's child, so onExit() would poll with a growing step:
            // poll with a short bounded one instead, to measure how long it outlived its JVM
            val jvmEnded = System.nanoTime()
            val deadline = jvmEnded + TimeUnit.SECONDS.toNanos(10)
            if (server != null) {
                while (!ended(server) && System.nanoTime() - deadline < 0) Thread.sleep(5)
                assertTrue(ended(server), "redis-server ${server.pid()} still runs 10 s after its JVM ended")
                println("[embedded redis] JVM exit code $exitCode: server ended ${(System.nanoTime() - jvmEnded) / 1_000_000} ms after its JVM")
            }
            // after a SIGKILL the watchdog shell kills the server, then deletes its files: a moment later
            while (Files.exists(dir) && System.nanoTime() - deadline < 0) Thread.sleep(5)
            assertFalse(Files.exists(dir), "the server's files were deleted: $dir")
        } finally {
            jvm.destroyForcibly()
            redis?.destroyForcibly()
        }
    }

    /**
     * Whether [process] has ended: gone, or a zombie (a killed orphan waits for init to collect it,
     * which can take a second or more, and Java counts a zombie as alive).
     */
    private fun ended(process: ProcessHandle): Boolean {
        if (!process.isAlive) return true
        val stat = runCatching { Files.readString(Path.of("/proc/${process.pid()}/stat")) }.getOrNull() ?: return false
        return stat.substringAfterLast(')').trim().startsWith("Z")
    }
}

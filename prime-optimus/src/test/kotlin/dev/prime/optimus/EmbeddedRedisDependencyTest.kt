package dev.prime.optimus

import dev.prime.PrimeException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.io.File
import java.net.URLClassLoader
import java.nio.file.Files
import java.nio.file.Path
import java.util.concurrent.TimeUnit

/**
 * The redis-server binaries live in the optional `dev.prime:prime-redis-embedded` artifact: a core
 * given no Redis URL on a class path without it (and no redis-server on the PATH) fails at once
 * with a message naming the dependency to add, and one whose class path has the artifact but no
 * binary for this machine says that instead.
 */
class EmbeddedRedisDependencyTest {

    @Test
    fun withoutTheArtifactANewCoreNamesTheDependencyToAdd(@TempDir dir: Path) {
        val emptyPath = Files.createDirectory(dir.resolve("bin"))
        val tmp = Files.createDirectory(dir.resolve("tmp"))
        val all = System.getProperty("java.class.path").split(File.pathSeparator)
        val withoutBinaries = all.filterNot { isEmbeddedRedis(it) }
        assertEquals(2, all.size - withoutBinaries.size, "the test class path holds prime-redis-embedded and its binaries: $all")

        val java = File(System.getProperty("java.home"), "bin/java").path
        val process = ProcessBuilder(java, "-Xmx128m", "-Djava.io.tmpdir=$tmp", "-cp", withoutBinaries.joinToString(File.pathSeparator), NoEmbeddedRedisMain::class.java.name)
            .redirectErrorStream(true)
            .also { it.environment()["PATH"] = emptyPath.toString() } // no redis-server on the PATH either
            .start()
        val output = try {
            assertTrue(process.waitFor(60, TimeUnit.SECONDS), "the JVM did not end within 60 s")
            process.inputStream.bufferedReader().readText()
        } finally {
            process.destroyForcibly()
        }
        val failure = output.lineSequence().firstOrNull { it.startsWith("FAILED ") || it == "STARTED" }
            ?: throw AssertionError("no result line; output:\n$output")
        assertTrue(failure.startsWith("FAILED ${PrimeException::class.java.name}: "), failure)
        assertTrue(failure.contains("Add the dependency dev.prime:prime-redis-embedded"), failure)
        assertTrue(failure.contains("<artifactId>prime-redis-embedded</artifactId>"), failure)
        assertTrue(failure.contains("runtimeOnly(\"dev.prime:prime-redis-embedded\")"), failure)
        assertTrue(failure.contains("redis-server 6.2+ on the PATH"), failure)
        assertTrue(failure.contains("redis:// URL"), failure)
        assertEquals(0, Files.list(tmp).use { it.count() }, "nothing was extracted or left in the temporary directory")
    }

    @Test
    fun theArtifactWithoutABinaryForThisMachineSaysSo(@TempDir tmp: Path) {
        val markerOnly = System.getProperty("java.class.path").split(File.pathSeparator)
            .filter { it.contains("prime-redis-embedded") }
            .map { File(it).toURI().toURL() }
        assertEquals(1, markerOnly.size, "the test class path holds prime-redis-embedded")
        URLClassLoader(markerOnly.toTypedArray(), null).use { loader ->
            val e = assertThrows(PrimeException::class.java) { RedisServerBinary.bundled(tmp, loader) }
            assertTrue(e.message!!.contains("dev.prime:prime-redis-embedded is on the class path"), e.message)
            assertTrue(e.message!!.contains("has no redis-server for this machine"), e.message)
            assertTrue(e.message!!.contains(RedisServerBinary.bundledResource()), e.message)
        }
    }

    private fun isEmbeddedRedis(entry: String): Boolean =
        entry.contains("prime-redis-embedded") || entry.replace(File.separatorChar, '/').contains("/org/signal/embedded-redis/")
}

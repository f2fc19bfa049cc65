package dev.prime.optimus

import dev.prime.PrimeException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertNotEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Files
import java.nio.file.Path
import java.nio.file.attribute.PosixFilePermissions

/**
 * The bundled redis-server is extracted into a directory only this user can write and checked
 * against a pinned SHA-256 before every start; a planted or tampered file is never executed.
 */
class RedisServerBinaryTest {

    /**
     * `prime-redis-embedded` promises binaries for Linux and macOS, x86-64 and arm64: on this
     * class path each of the four is found under the name its platform looks for, has its
     * pinned SHA-256 and is extracted.
     */
    @Test
    fun theArtifactBringsAPinnedBinaryForLinuxAndMacOsOnX8664AndArm64(@TempDir tmp: Path) {
        val platforms = mapOf(
            ("Linux" to "amd64") to "linux-amd64",
            ("Linux" to "aarch64") to "linux-arm64",
            ("Mac OS X" to "x86_64") to "darwin-amd64",
            ("Mac OS X" to "aarch64") to "darwin-arm64",
        )
        val osName = System.getProperty("os.name")
        val osArch = System.getProperty("os.arch")
        val found = mutableMapOf<String, String>()
        try {
            for ((platform, suffix) in platforms) {
                System.setProperty("os.name", platform.first)
                System.setProperty("os.arch", platform.second)
                val root = Files.createDirectories(tmp.resolve(suffix))
                found[suffix] = try {
                    val binary = RedisServerBinary.bundled(root)
                    binary.verify()
                    binary.path.fileName.toString()
                } catch (e: PrimeException) {
                    "refused: ${e.message}"
                }
            }
        } finally {
            System.setProperty("os.name", osName)
            System.setProperty("os.arch", osArch)
        }
        assertEquals(
            platforms.values.associateWith { "redis-server-${RedisServerBinary.BUNDLED_VERSION}-$it" },
            found,
        )
    }

    @Test
    fun aFilePlantedInTheSharedTempDirectoryIsNotExecuted(@TempDir tmp: Path) {
        val marker = tmp.resolve("planted-ran")
        val resource = RedisServerBinary.bundledResource()
        val size = RedisServerBinary::class.java.getResourceAsStream("/$resource")!!.use { it.readAllBytes().size }
        // where versions before the fix extracted to and ran from, unchecked if the size matched
        val planted = tmp.resolve("prime-redis-${RedisServerBinary.BUNDLED_VERSION}").resolve(resource)
        Files.createDirectories(planted.parent)
        Files.write(planted, script(marker, size))
        Files.setPosixFilePermissions(planted, PosixFilePermissions.fromString("rwxrwxrwx"))

        val binary = RedisServerBinary.bundled(tmp)
        EmbeddedRedis.builder().binary(binary).start().use { assertTrue(it.isRunning) }
        assertFalse(Files.exists(marker), "the planted file was executed")
        assertNotEquals(planted, binary.path)
        assertEquals("rwx------", PosixFilePermissions.toString(Files.getPosixFilePermissions(binary.path.parent)))
    }

    @Test
    fun aTamperedBinaryInTheExtractionDirectoryIsRefused(@TempDir tmp: Path) {
        val marker = tmp.resolve("tampered-ran")
        val binary = RedisServerBinary.bundled(tmp)
        EmbeddedRedis.builder().binary(binary).start().use { redis ->
            redis.kill()
            Files.write(binary.path, script(marker, Files.size(binary.path).toInt()))
            val e = assertThrows(PrimeException::class.java) { redis.restart() }
            assertTrue(e.message!!.contains("SHA-256"), e.message)
        }
        assertFalse(Files.exists(marker), "the tampered binary was executed")
        // extracting again replaces it with the genuine binary
        val again = RedisServerBinary.bundled(tmp)
        EmbeddedRedis.builder().binary(again).start().use { assertTrue(it.isRunning) }
        assertFalse(Files.exists(marker))
    }

    @Test
    fun aSharedExtractionDirectoryIsNotUsed(@TempDir tmp: Path) {
        val dir = RedisServerBinary.bundled(tmp).path.parent
        Files.setPosixFilePermissions(dir, PosixFilePermissions.fromString("rwxrwxrwx"))
        val again = RedisServerBinary.bundled(tmp)
        assertNotEquals(dir, again.path.parent, "a directory others may write is not reused")
        assertEquals("rwx------", PosixFilePermissions.toString(Files.getPosixFilePermissions(again.path.parent)))
    }

    /** A shell script of exactly [size] bytes that leaves [marker] if it runs. */
    private fun script(marker: Path, size: Int): ByteArray {
        val head = "#!/bin/sh\ntouch '$marker'\nexit 1\n#".toByteArray()
        return head + ByteArray(size - head.size) { 'x'.code.toByte() }
    }
}

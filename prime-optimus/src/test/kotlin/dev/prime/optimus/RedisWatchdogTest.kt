package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Assumptions.assumeTrue
import org.junit.jupiter.api.BeforeEach
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.net.ServerSocket
import java.nio.file.Files
import java.nio.file.Path
import java.util.concurrent.TimeUnit

/**
 * What a fired [RedisWatchdog] does (the end of its JVM, played by closing its pipe): it kills the
 * process only if it is a `redis-server`, and deletes the directory it was given.
 */
class RedisWatchdogTest {

    @BeforeEach
    fun needsAShell() {
        assumeTrue(Files.isExecutable(Path.of("/bin/sh")), "the watchdog needs /bin/sh")
    }

    @Test
    fun aFiredWatchdogKillsItsServerAndDeletesItsDirectory(@TempDir tmp: Path) {
        val port = ServerSocket(0).use { it.localPort }
        val server = ProcessBuilder(RedisServerBinary.locate().path.toString(), "--port", "$port", "--bind", "127.0.0.1", "--save", "", "--appendonly", "no")
            .redirectOutput(ProcessBuilder.Redirect.DISCARD)
            .redirectErrorStream(true)
            .start()
        try {
            val dir = Files.createDirectory(tmp.resolve("server-files"))
            val watchdog = RedisWatchdog.arm(server.pid(), dir) ?: throw AssertionError("no watchdog was armed")
            assertTrue(watchdog.fireForTest(), "the shell ended within 10 s")
            assertTrue(server.waitFor(10, TimeUnit.SECONDS), "the redis-server was killed")
            assertFalse(Files.exists(dir), "its directory was deleted")
        } finally {
            server.destroyForcibly()
        }
    }

    @Test
    fun aPidThatIsNoLongerARedisServerIsLeftAlone(@TempDir tmp: Path) {
        val other = ProcessBuilder("/bin/sh", "-c", "read -r _").start() // any program but redis-server
        try {
            val dir = Files.createDirectory(tmp.resolve("server-files"))
            val watchdog = RedisWatchdog.arm(other.pid(), dir) ?: throw AssertionError("no watchdog was armed")
            assertTrue(watchdog.fireForTest(), "the shell ended within 10 s")
            assertTrue(other.isAlive, "a process that is not a redis-server was not killed")
            assertFalse(Files.exists(dir), "the directory was deleted all the same")
        } finally {
            other.destroyForcibly()
        }
    }
}

package dev.prime.optimus

import dev.prime.PrimeException
import java.io.File
import java.io.IOException
import java.nio.file.Files
import java.nio.file.Path
import java.nio.file.StandardCopyOption
import java.nio.file.attribute.PosixFilePermissions
import java.util.Locale
import java.util.concurrent.TimeUnit

/**
 * Finds a `redis-server` able to run Optimus (6.2 or newer, for `LMOVE`/`BLMOVE`): the one on the
 * `PATH` if it is new enough, else the binary bundled for this OS and CPU, extracted once into
 * the temporary directory (written to a private file and moved into place, so concurrent JVMs
 * never run a half-written binary).
 */
internal object RedisServerBinary {
    private const val BUNDLED_VERSION = "7.0.15"
    private val MINIMUM = listOf(6, 2)

    fun locate(): Path = onPath() ?: bundled()

    private fun onPath(): Path? {
        val path = System.getenv("PATH") ?: return null
        for (dir in path.split(File.pathSeparator)) {
            if (dir.isEmpty()) continue
            val candidate = Path.of(dir, "redis-server")
            if (Files.isExecutable(candidate) && isRecentEnough(candidate)) return candidate
        }
        return null
    }

    private fun isRecentEnough(binary: Path): Boolean = try {
        val process = ProcessBuilder(binary.toString(), "--version").redirectErrorStream(true).start()
        val output = process.inputStream.bufferedReader().use { it.readText() }
        if (!process.waitFor(5, TimeUnit.SECONDS)) {
            process.destroyForcibly()
            false
        } else {
            val version = Regex("v=(\\d+)\\.(\\d+)").find(output)?.groupValues?.drop(1)?.map { it.toInt() }
            version != null && (version[0] > MINIMUM[0] || (version[0] == MINIMUM[0] && version[1] >= MINIMUM[1]))
        }
    } catch (_: IOException) {
        false
    }

    private fun bundled(): Path {
        val resource = "redis-server-$BUNDLED_VERSION-${os()}-${arch()}"
        val target = Path.of(System.getProperty("java.io.tmpdir"), "prime-redis-$BUNDLED_VERSION", resource)
        val stream = RedisServerBinary::class.java.getResourceAsStream("/$resource")
            ?: throw PrimeException(
                "no bundled redis-server for this machine (looked for resource '$resource'); install Redis " +
                    "6.2+ and put redis-server on the PATH, or give OptimusCore a redis:// URL",
            )
        stream.use { input ->
            Files.createDirectories(target.parent)
            val bytes = input.readAllBytes()
            if (Files.isExecutable(target) && Files.size(target) == bytes.size.toLong()) return target
            val partial = Files.createTempFile(target.parent, "redis-server-", ".part")
            Files.write(partial, bytes)
            try {
                Files.setPosixFilePermissions(partial, PosixFilePermissions.fromString("rwxr-xr-x"))
            } catch (_: UnsupportedOperationException) {
                partial.toFile().setExecutable(true)
            }
            Files.move(partial, target, StandardCopyOption.REPLACE_EXISTING, StandardCopyOption.ATOMIC_MOVE)
        }
        return target
    }

    private fun os(): String {
        val name = System.getProperty("os.name").lowercase(Locale.ROOT)
        return when {
            name.contains("linux") -> "linux"
            name.contains("mac") || name.contains("darwin") -> "darwin"
            else -> throw PrimeException(
                "no bundled redis-server for '$name'; install Redis 6.2+ and put redis-server on the PATH, " +
                    "or give OptimusCore a redis:// URL",
            )
        }
    }

    private fun arch(): String = when (val arch = System.getProperty("os.arch").lowercase(Locale.ROOT)) {
        "amd64", "x86_64" -> "amd64"
        "aarch64", "arm64" -> "arm64"
        "x86", "i386", "i686" -> "386"
        else -> arch
    }
}

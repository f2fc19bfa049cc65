package dev.prime.optimus

import dev.prime.PrimeException
import org.slf4j.LoggerFactory
import java.io.File
import java.io.IOException
import java.nio.file.FileAlreadyExistsException
import java.nio.file.Files
import java.nio.file.LinkOption
import java.nio.file.Path
import java.nio.file.StandardCopyOption
import java.nio.file.attribute.PosixFileAttributes
import java.nio.file.attribute.PosixFilePermission
import java.nio.file.attribute.PosixFilePermissions
import java.security.MessageDigest
import java.util.Locale
import java.util.concurrent.TimeUnit

/**
 * Finds a `redis-server` able to run Optimus (6.2 or newer, for `LMOVE`/`BLMOVE`): the one on the
 * `PATH` if it is new enough, else the binary for this OS and CPU that the optional
 * `dev.prime:prime-redis-embedded` artifact puts on the class path (through
 * `org.signal:embedded-redis`), found by its well-known resource name
 * (`redis-server-<version>-<os>-<arch>`): prime-optimus does not depend on that artifact, which
 * depends on no Prime module either, so its own tests can use it without a build cycle. Without
 * it (and with nothing on the `PATH`) the failure names the dependency to add.
 *
 * Design note (safety). A file in a shared temporary directory can be planted or replaced by any
 * local user, so the bundled binary is extracted into a directory only the current user can
 * write: `prime-redis-<version>-<user>` in the temporary directory, created with owner-only
 * permissions, and reused only if it is still a real directory of this user that nobody else
 * can write (else a fresh private directory is made). The binary must have the SHA-256 pinned
 * below: checked on the bytes in the jar, on a file found already extracted (replaced if it
 * differs), and by [EmbeddedRedis] before every start ([Binary.verify]), which refuses to run
 * anything else. A binary on the `PATH` or given by the user is the user's choice and runs
 * unchecked.
 */
internal object RedisServerBinary {
    const val BUNDLED_VERSION: String = "7.0.15"
    private val MINIMUM = listOf(6, 2)
    private val LOG = LoggerFactory.getLogger(RedisServerBinary::class.java)
    private val OWNER_ONLY = PosixFilePermissions.fromString("rwx------")
    private const val ARTIFACT = "dev.prime:prime-redis-embedded"
    private const val MARKER = "META-INF/dev.prime/redis-embedded.properties"

    /** SHA-256 of the binaries of `org.signal:embedded-redis` 0.9.1, by resource name. */
    private val PINS = mapOf(
        "redis-server-7.0.15-darwin-amd64" to "e22a3d9147802bba0724efb2e446c49e1e514e76ff8031bb6d44b8628400d8f3",
        "redis-server-7.0.15-darwin-arm64" to "07838a2eb6f5961c89d8e6f1f83482de355dfc6bb04e05bfb00ae1f137dee129",
        "redis-server-7.0.15-linux-386" to "19106984e15b7e7ce22c9a3296fe6a5f85c43a72894144f98b1fb572b823a936",
        "redis-server-7.0.15-linux-amd64" to "c0cdeef856b3410fd99d6ec6fc6a20302e69059b00ce5d6abab7b3e5069ea91e",
        "redis-server-7.0.15-linux-arm64" to "d5c7ff117caf45d7dc2f59c1f956e1830438779947d66aa5647c2cdcc16eca50",
    )

    /** A `redis-server` to run and the SHA-256 it must have at every start (`null`: the user's, unchecked). */
    class Binary(val path: Path, private val sha256: String?) {
        /** Refuses (with [PrimeException]) a pinned binary whose content is not the pinned one. */
        fun verify() {
            val pin = sha256 ?: return
            val actual = try {
                sha256(path)
            } catch (e: IOException) {
                throw PrimeException("cannot read the redis-server binary $path to check it: $e", e)
            }
            if (actual != pin) {
                throw PrimeException(
                    "refusing to run $path: its SHA-256 is $actual, not the $pin pinned for the bundled redis-server " +
                        "$BUNDLED_VERSION, so it was changed after extraction. Delete it (it is extracted again), or " +
                        "install Redis 6.2+ and put redis-server on the PATH",
                )
            }
        }

        override fun toString(): String = path.toString()
    }

    fun locate(): Binary = onPath()?.let { Binary(it, null) } ?: bundled(Path.of(System.getProperty("java.io.tmpdir")))

    /** The name of the resource bundled for this OS and CPU. */
    fun bundledResource(): String = "redis-server-$BUNDLED_VERSION-${os()}-${arch()}"

    /**
     * The bundled binary, read through [loader] and extracted (if needed) into a private directory
     * under [tmpRoot]. A class loader, not a class, looks the resource up: resources at the top of
     * another jar are not visible to a class of a named module (prime-optimus on the module path).
     */
    fun bundled(tmpRoot: Path, loader: ClassLoader = RedisServerBinary::class.java.classLoader): Binary {
        val resource = bundledResource()
        val pin = PINS[resource] ?: throw noBinary("no pinned SHA-256 for '$resource'")
        val bytes = loader.getResourceAsStream(resource)?.use { it.readAllBytes() }
            ?: throw missingBinary(resource, loader)
        if (sha256(bytes) != pin) throw noBinary("the bundled '$resource' does not have its pinned SHA-256 (an altered jar?)")
        val dir = privateDirectory(tmpRoot)
        val target = dir.resolve(resource)
        if (Files.isRegularFile(target, LinkOption.NOFOLLOW_LINKS)) {
            if (sha256(target) == pin) return Binary(target, pin)
            LOG.warn("the extracted redis-server {} was changed; extracting it again", target)
        }
        val partial = Files.createTempFile(dir, "redis-server-", ".part", PosixFilePermissions.asFileAttribute(OWNER_ONLY))
        try {
            Files.write(partial, bytes)
            Files.move(partial, target, StandardCopyOption.REPLACE_EXISTING, StandardCopyOption.ATOMIC_MOVE)
        } finally {
            Files.deleteIfExists(partial)
        }
        return Binary(target, pin)
    }

    /** `prime-redis-<version>-<user>` under [root] if it is (or can be made) this user's alone, else a fresh private directory. */
    private fun privateDirectory(root: Path): Path {
        val user = System.getProperty("user.name").orEmpty().replace(Regex("[^A-Za-z0-9._-]"), "_")
        val dir = root.resolve("prime-redis-$BUNDLED_VERSION-$user")
        try {
            Files.createDirectory(dir, PosixFilePermissions.asFileAttribute(OWNER_ONLY))
        } catch (_: FileAlreadyExistsException) {
            // reused below if it is still private
        }
        if (isPrivate(dir)) return dir
        LOG.warn("{} is not a directory only this user can write; extracting redis-server into a fresh one", dir)
        val fresh = Files.createTempDirectory(root, "prime-redis-", PosixFilePermissions.asFileAttribute(OWNER_ONLY))
        fresh.toFile().deleteOnExit()
        fresh.resolve(bundledResource()).toFile().deleteOnExit() // registered later: deleted before its directory
        return fresh
    }

    /** A real directory (not a link), owned by this user, that no one else may write. */
    private fun isPrivate(dir: Path): Boolean {
        val attributes = Files.readAttributes(dir, PosixFileAttributes::class.java, LinkOption.NOFOLLOW_LINKS)
        if (!attributes.isDirectory || attributes.isSymbolicLink) return false
        val me = dir.fileSystem.userPrincipalLookupService.lookupPrincipalByName(System.getProperty("user.name"))
        val othersMayWrite = PosixFilePermission.GROUP_WRITE in attributes.permissions() ||
            PosixFilePermission.OTHERS_WRITE in attributes.permissions()
        return attributes.owner() == me && !othersMayWrite
    }

    private fun sha256(bytes: ByteArray): String = hex(MessageDigest.getInstance("SHA-256").digest(bytes))

    private fun sha256(file: Path): String {
        val digest = MessageDigest.getInstance("SHA-256")
        Files.newInputStream(file, LinkOption.NOFOLLOW_LINKS).use { input ->
            val buffer = ByteArray(64 * 1024)
            while (true) {
                val n = input.read(buffer)
                if (n < 0) break
                digest.update(buffer, 0, n)
            }
        }
        return hex(digest.digest())
    }

    private fun hex(bytes: ByteArray) = bytes.joinToString("") { "%02x".format(it) }

    /** The resource is missing: say whether the artifact is absent (name it) or lacks this platform. */
    private fun missingBinary(resource: String, loader: ClassLoader): PrimeException {
        val marker = loader.getResource(MARKER) ?: return PrimeException(
            "OptimusCore was given no Redis URL, so it starts a redis-server of its own, but found none: there is no " +
                "redis-server 6.2+ on the PATH and no embedded one on the class path. Add the dependency " +
                "$ARTIFACT (Maven: <dependency><groupId>dev.prime</groupId><artifactId>prime-redis-embedded" +
                "</artifactId></dependency>, version from prime-bom; Gradle: runtimeOnly(\"$ARTIFACT\")), or put " +
                "redis-server 6.2+ on the PATH, or give OptimusCore a redis:// URL (OptimusCore.builder().redis(url))",
        )
        return noBinary(
            "$ARTIFACT is on the class path ($marker) but has no redis-server for this machine (looked for resource " +
                "'$resource'; is its version the one prime-bom names?)",
        )
    }

    private fun noBinary(why: String) = PrimeException(
        "$why; install Redis 6.2+ and put redis-server on the PATH, or give OptimusCore a redis:// URL",
    )

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

    private fun os(): String {
        val name = System.getProperty("os.name").lowercase(Locale.ROOT)
        return when {
            name.contains("linux") -> "linux"
            name.contains("mac") || name.contains("darwin") -> "darwin"
            else -> throw noBinary("no bundled redis-server for '$name'")
        }
    }

    private fun arch(): String = when (val arch = System.getProperty("os.arch").lowercase(Locale.ROOT)) {
        "amd64", "x86_64" -> "amd64"
        "aarch64", "arm64" -> "arm64"
        "x86", "i386", "i686" -> "386"
        else -> arch
    }
}

package dev.prime.optimus

import dev.prime.PrimeException
import redis.clients.jedis.DefaultJedisClientConfig
import redis.clients.jedis.HostAndPort
import redis.clients.jedis.Jedis
import java.io.IOException
import java.io.UncheckedIOException
import java.net.ServerSocket
import java.nio.file.Files
import java.nio.file.Path
import java.time.Duration
import java.util.concurrent.TimeUnit

/**
 * A real `redis-server` process for development and tests, owned by this object.
 *
 * [OptimusCore] starts one when it is given no Redis URL, so examples and tests run on a machine
 * with nothing installed. The server binary is a `redis-server` found on the `PATH` (version 6.2
 * or newer), else the static binary for Linux and macOS (x86-64 and arm64) that the optional
 * `dev.prime:prime-redis-embedded` artifact puts on the class path (without it, [Builder.start]
 * fails with a message naming that dependency), extracted once into a directory of the temporary
 * directory that only the current user can write, and checked against its pinned SHA-256 before
 * every start (see [RedisServerBinary]): a planted or changed file is refused, never run.
 *
 * The server listens on 127.0.0.1 only, on a free port unless one is given. By default it keeps
 * nothing on disk; [Builder.appendOnlyDir] makes every acknowledged write durable
 * (`appendfsync always`), so the server can be stopped and started again without losing data.
 *
 * An [EmbeddedRedis] that is never closed does not outlive its JVM. When the JVM exits normally,
 * on SIGTERM or on Ctrl-C, a shutdown hook kills the server and deletes its files (a directory
 * given to [Builder.appendOnlyDir] is kept). Where `/bin/sh` exists (Linux, macOS), a JVM killed
 * with SIGKILL or crashed is covered too: a small shell process kills the server within a second
 * of the JVM's end and deletes its files.
 *
 * Design note: no thread is started. The server's log goes to a file in its working directory
 * (a pipe nobody reads would stall the server once full). The shutdown hook is registered only
 * while the server runs ([close] removes it), and the shell is a [RedisWatchdog], disarmed
 * whenever this object stops the server itself.
 */
public class EmbeddedRedis private constructor(
    private val executable: RedisServerBinary.Binary,
    private val dir: Path,
    private val ownsDir: Boolean,
    private val persistent: Boolean,
    private val startTimeout: Duration,
    /** The port the server listens on. */
    public val port: Int,
    private val arguments: List<String>,
) : AutoCloseable {

    private val lock = Any()
    @Volatile private var process: Process? = null // written under lock
    @Volatile private var watchdog: RedisWatchdog? = null // written under lock, with process
    private var closed = false // guarded by lock
    private val hook = Thread({ stopAtExit() }, "prime-embedded-redis-stop")

    /** The URL that reaches this server, `redis://127.0.0.1:<port>`. */
    public val uri: String get() = "redis://127.0.0.1:$port"

    /** Whether the server process is running. */
    public val isRunning: Boolean get() = synchronized(lock) { process?.isAlive == true }

    /**
     * Stops the server (and deletes its files unless they were asked to persist). Idempotent.
     */
    override fun close() {
        synchronized(lock) {
            if (closed) return
            closed = true
            stopProcess(graceful = true)
        }
        try {
            Runtime.getRuntime().removeShutdownHook(hook)
        } catch (_: IllegalStateException) {
            // the JVM is shutting down already; the hook runs anyway
        }
        if (ownsDir) deleteTree(dir)
    }

    /**
     * The shutdown hook's work: kills the server and deletes its own files. No lock is taken, so
     * an exit while another thread holds it (a [close] or [restart] in progress) cannot hang the
     * JVM; the wait for the process is bounded.
     */
    private fun stopAtExit() {
        watchdog?.disarm()
        val running = process // null if the server was stopped or crashed (kill) and not restarted: its files stay until here
        if (running != null) {
            running.destroyForcibly()
            try {
                running.waitFor(STOP_TIMEOUT_S, TimeUnit.SECONDS)
            } catch (_: InterruptedException) {
                return
            }
        }
        if (ownsDir) deleteTree(dir)
    }

    /** Kills the server without letting it save anything: a crash, for tests of recovery. */
    internal fun kill() {
        synchronized(lock) { stopProcess(graceful = false) }
    }

    /** Starts the server again on the same port and directory after [kill]. */
    internal fun restart() {
        synchronized(lock) {
            check(!closed) { "embedded Redis on port $port is closed" }
            stopProcess(graceful = false)
            launch()
        }
    }

    override fun toString(): String = "EmbeddedRedis[$uri, ${if (isRunning) "running" else "stopped"}]"

    private fun launch() {
        executable.verify()
        val log = dir.resolve("redis.log")
        val command = mutableListOf(
            executable.path.toString(),
            "--port", port.toString(),
            "--bind", "127.0.0.1",
            "--protected-mode", "no",
            "--daemonize", "no",
            "--dir", dir.toString(),
            "--save", "",
        )
        if (persistent) {
            command += listOf("--appendonly", "yes", "--appendfsync", "always")
        } else {
            command += listOf("--appendonly", "no")
        }
        command += arguments
        val started = ProcessBuilder(command)
            .redirectErrorStream(true)
            .redirectOutput(ProcessBuilder.Redirect.appendTo(log.toFile()))
            .start()
        process = started
        val deadline = System.nanoTime() + startTimeout.toNanos()
        while (true) {
            if (!started.isAlive) {
                throw PrimeException(
                    "redis-server ($executable) exited with code ${started.exitValue()} while starting on " +
                        "port $port; its log ends with:\n${tail(log)}",
                )
            }
            if (answers(started.pid())) {
                watchdog = RedisWatchdog.arm(started.pid(), dir.takeIf { ownsDir })
                return
            }
            if (System.nanoTime() > deadline) {
                started.destroyForcibly()
                throw PrimeException(
                    "redis-server did not answer on port $port within $startTimeout; its log ends with:\n${tail(log)}",
                )
            }
            Thread.sleep(PING_INTERVAL_MS)
        }
    }

    /**
     * Whether the server on [port] is the process [pid] (another server may hold the port) and has
     * finished loading its data.
     */
    private fun answers(pid: Long): Boolean = try {
        Jedis(HostAndPort("127.0.0.1", port), DefaultJedisClientConfig.builder().resp2().autoNegotiateProtocol(false).timeoutMillis(500).build())
            .use { jedis ->
                val info = jedis.info().lineSequence().map { it.trim() }.toSet()
                "process_id:$pid" in info && "loading:0" in info
            }
    } catch (_: Exception) {
        false
    }

    /** Stops the process; an interrupt of the calling thread cuts the wait short (killing it) and stays set. */
    private fun stopProcess(graceful: Boolean) {
        val running = process ?: return
        process = null
        watchdog?.disarm()
        watchdog = null
        if (graceful) running.destroy() else running.destroyForcibly()
        try {
            if (!running.waitFor(STOP_TIMEOUT_S, TimeUnit.SECONDS)) {
                running.destroyForcibly()
                running.waitFor(STOP_TIMEOUT_S, TimeUnit.SECONDS)
            }
        } catch (_: InterruptedException) {
            running.destroyForcibly()
            Thread.currentThread().interrupt()
        }
    }

    /** Settings of an [EmbeddedRedis]; [start] launches it. */
    public class Builder internal constructor() {
        private var port = 0
        private var appendOnlyDir: Path? = null
        private var executable: RedisServerBinary.Binary? = null
        private var startTimeout = Duration.ofSeconds(20)
        private var arguments = emptyList<String>()

        /** Listens on [port] (1–65535); by default a free port is picked. */
        public fun port(port: Int): Builder = apply {
            require(port in 1..65535) { "port must be within 1..65535, was $port" }
            this.port = port
        }

        /**
         * Keeps the data in [dir] with an append-only file synced on every write, so a restarted
         * server has every acknowledged value. The directory is created if needed and kept.
         */
        public fun appendOnlyDir(dir: Path): Builder = apply { this.appendOnlyDir = dir }

        /** Uses this `redis-server` binary instead of looking for one. */
        public fun executable(executable: Path): Builder = apply {
            require(Files.isExecutable(executable)) { "'$executable' is not an executable file" }
            this.executable = RedisServerBinary.Binary(executable, null)
        }

        /**
         * More `redis-server` options, after the ones this class sets (a later option wins), e.g.
         * `--cluster-enabled yes` for the nodes of a test cluster.
         */
        internal fun arguments(vararg options: String): Builder = apply { this.arguments = options.toList() }

        /** Uses [binary] (checked against its pin before every start). */
        internal fun binary(binary: RedisServerBinary.Binary): Builder = apply { this.executable = binary }

        /** How long to wait for the server to answer after launching it (default 20 s). */
        public fun startTimeout(timeout: Duration): Builder = apply {
            require(!timeout.isNegative && !timeout.isZero) { "start timeout must be positive, was $timeout" }
            this.startTimeout = timeout
        }

        /**
         * Launches the server and waits until it answers.
         *
         * @throws PrimeException if no binary fits this machine or the server does not start
         */
        public fun start(): EmbeddedRedis {
            val binary = executable ?: RedisServerBinary.locate()
            val persistentDir = appendOnlyDir
            val dir = persistentDir?.also { Files.createDirectories(it) } ?: Files.createTempDirectory("prime-redis-")
            var attempt = 0
            while (true) {
                val chosen = if (port != 0) port else freePort()
                val redis = EmbeddedRedis(binary, dir, persistentDir == null, persistentDir != null, startTimeout, chosen, arguments)
                try {
                    synchronized(redis.lock) { redis.launch() }
                    Runtime.getRuntime().addShutdownHook(redis.hook)
                    return redis
                } catch (e: PrimeException) {
                    attempt++
                    // a free port can be taken between picking it and binding it: try another
                    if (port != 0 || attempt >= PORT_ATTEMPTS) {
                        if (persistentDir == null) deleteTree(dir)
                        throw e
                    }
                }
            }
        }
    }

    public companion object {
        private const val PING_INTERVAL_MS = 10L
        private const val STOP_TIMEOUT_S = 10L
        private const val PORT_ATTEMPTS = 3

        /** Starts a server on a free port, with nothing kept on disk. */
        @JvmStatic
        public fun start(): EmbeddedRedis = builder().start()

        /** Settings for a server; call [Builder.start]. */
        @JvmStatic
        public fun builder(): Builder = Builder()

        private fun freePort(): Int = ServerSocket(0).use { it.localPort }

        private fun tail(log: Path): String = try {
            Files.readAllLines(log).takeLast(10).joinToString("\n")
        } catch (e: IOException) {
            "(no log: ${e.message})"
        }

        private fun deleteTree(dir: Path) {
            try {
                Files.walk(dir).use { paths ->
                    paths.sorted(Comparator.reverseOrder()).forEach { Files.deleteIfExists(it) }
                }
            } catch (_: IOException) {
                // a temporary directory left behind is harmless
            } catch (_: UncheckedIOException) {
                // a file deleted meanwhile by a racing close() or shutdown hook
            }
        }
    }
}

package dev.prime.optimus

import java.io.IOException
import java.nio.file.Files
import java.nio.file.Path
import java.util.concurrent.TimeUnit

/**
 * Stops an [EmbeddedRedis] server when the JVM that started it ends without running its shutdown
 * hooks (SIGKILL, a crash of the JVM).
 *
 * Design note: a `/bin/sh` child reads its standard input, a pipe whose only writer is this JVM
 * (a process this JVM starts later does not inherit it). However this JVM ends, the kernel closes
 * the pipe; the shell reads end-of-file, kills the server if the process with its pid is still a
 * `redis-server` (a pid the system gave to another program since is left alone), and deletes the
 * server's directory when it is the server's own. No thread runs in this JVM. The owner keeps the
 * watchdog reachable while it is armed: a pipe that is collected is closed by its cleaner, and that
 * would fire the watchdog early. [disarm] ends the shell without firing it, for a server this JVM
 * stops itself. Where there is no `/bin/sh`, no watchdog is armed.
 */
internal class RedisWatchdog private constructor(private val shell: Process) {

    /** Ends the watchdog without touching the server (the caller stops it); waits at most 10 s. */
    fun disarm() {
        shell.destroyForcibly()
        try {
            shell.waitFor(DISARM_TIMEOUT_S, TimeUnit.SECONDS)
        } catch (_: InterruptedException) {
            Thread.currentThread().interrupt()
        }
    }

    /**
     * Fires the watchdog as the end of this JVM would: closes its pipe and waits at most 10 s for
     * the shell to act. For tests.
     */
    internal fun fireForTest(): Boolean {
        shell.outputStream.close()
        return try {
            shell.waitFor(DISARM_TIMEOUT_S, TimeUnit.SECONDS)
        } catch (_: InterruptedException) {
            Thread.currentThread().interrupt()
            false
        }
    }

    internal companion object {
        private const val DISARM_TIMEOUT_S = 10L
        private val SHELL: Path = Path.of("/bin/sh")

        /** What the shell runs; `$1` is the server's pid, `$2` the directory to delete or empty. */
        private const val SCRIPT = """
            read -r _
            if [ -r "/proc/${'$'}1/comm" ]; then name=${'$'}(cat "/proc/${'$'}1/comm"); else name=${'$'}(ps -o comm= -p "${'$'}1" 2>/dev/null); fi
            case "${'$'}name" in *redis*) kill -9 "${'$'}1" 2>/dev/null ;; esac
            if [ -n "${'$'}2" ]; then rm -rf -- "${'$'}2"; fi
        """

        /**
         * Watches the server [serverPid] for this JVM; at its end the shell kills it and deletes
         * [ownDir] if given. Null where no shell can be started.
         */
        fun arm(serverPid: Long, ownDir: Path?): RedisWatchdog? {
            if (!Files.isExecutable(SHELL)) return null
            return try {
                val shell = ProcessBuilder(SHELL.toString(), "-c", SCRIPT, "prime-redis-watchdog", serverPid.toString(), ownDir?.toString() ?: "")
                    .redirectOutput(ProcessBuilder.Redirect.DISCARD)
                    .redirectError(ProcessBuilder.Redirect.DISCARD)
                    .start()
                RedisWatchdog(shell)
            } catch (_: IOException) {
                null
            }
        }
    }
}

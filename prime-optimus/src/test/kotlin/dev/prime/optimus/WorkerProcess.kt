package dev.prime.optimus

import java.io.File
import java.io.IOException
import java.util.Collections
import java.util.concurrent.LinkedBlockingQueue
import java.util.concurrent.TimeUnit
import kotlin.concurrent.thread

/**
 * A worker JVM running a test main class of this module, for tests that kill real processes.
 * Its output (stdout and stderr) is kept for failure messages; [awaitLine] waits for a line.
 */
internal class WorkerProcess private constructor(private val process: Process) : AutoCloseable {
    private val lines: MutableList<String> = Collections.synchronizedList(mutableListOf<String>())
    private val fresh = LinkedBlockingQueue<String>()
    private val pump = thread(name = "lease-test-worker-output", isDaemon = true) {
        try {
            process.inputStream.bufferedReader().useLines { all ->
                all.forEach { line ->
                    lines += line
                    fresh += line
                }
            }
        } catch (_: IOException) {
            // destroying the process closed its output: it ends here
        }
        fresh += END
    }

    val pid: Long get() = process.pid()

    fun output(): String = synchronized(lines) { lines.joinToString("\n") }

    /** The next line starting with [prefix], waiting at most [seconds]. */
    fun awaitLine(prefix: String, seconds: Long = PATIENCE_S): String = awaitLine(prefix, seconds) { it.startsWith(prefix) }

    /** The next line containing [text], waiting at most [seconds]. */
    fun awaitLineContaining(text: String, seconds: Long = PATIENCE_S): String = awaitLine(text, seconds) { it.contains(text) }

    private fun awaitLine(what: String, seconds: Long, wanted: (String) -> Boolean): String {
        val deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(seconds)
        while (true) {
            val left = deadline - System.nanoTime()
            val line = fresh.poll(left.coerceAtLeast(0), TimeUnit.NANOSECONDS)
                ?: throw AssertionError("no line '$what' from the worker within $seconds s; its output:\n${output()}")
            if (line === END) throw AssertionError("the worker ended before '$what'; its output:\n${output()}")
            if (wanted(line)) return line
        }
    }

    fun send(line: String) {
        process.outputStream.write("$line\n".toByteArray())
        process.outputStream.flush()
    }

    /** Kills the worker at once (SIGKILL), as a crash would. */
    fun kill() {
        process.destroyForcibly()
        check(process.waitFor(PATIENCE_S, TimeUnit.SECONDS)) { "the worker did not die" }
    }

    override fun close() {
        process.destroyForcibly()
        process.waitFor(PATIENCE_S, TimeUnit.SECONDS)
        pump.join(TimeUnit.SECONDS.toMillis(PATIENCE_S))
    }

    companion object {
        private const val PATIENCE_S = 60L
        private val END = String(charArrayOf('\u0000'))

        fun start(main: Class<*>, vararg args: String): WorkerProcess {
            val java = File(System.getProperty("java.home"), "bin/java").path
            val command = listOf(java, "-Xmx256m", "-cp", System.getProperty("java.class.path"), main.name) + args
            return WorkerProcess(ProcessBuilder(command).redirectErrorStream(true).start())
        }
    }
}

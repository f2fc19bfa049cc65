package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import java.io.File
import java.io.IOException
import java.time.Duration
import java.util.Collections
import java.util.Optional
import java.util.concurrent.CompletableFuture
import java.util.concurrent.TimeUnit
import kotlin.concurrent.thread

/**
 * One topology over two JVMs on one Redis: this process hosts "inc" and reads the output; a
 * second JVM ([RemoteWorkerMain]) hosts "double" and "square". Values go out, through the other
 * process and back, all of them, in order; a synchronous call runs in the other process; and
 * values published while the worker is dead wait in Redis for the next one.
 */
class TwoProcessTest {

    @Test
    fun valuesFlowThroughTheOtherProcessAndWaitForItWhenItIsGone() {
        val coreName = "two-process"
        EmbeddedRedis.start().use { redis ->
            val config = CoreConfig.builder().name(coreName).build()
            OptimusCore.builder().config(config).redis(redis.uri).hosts(TwoProcessTopology.TEST_SERVICES).build().use { core ->
                val numbers = EventBlock<Int>()
                val declared = TwoProcessTopology.declare(core, numbers)
                val output = declared.output.reader()
                core.start()
                assertEquals(setOf("inc"), core.serviceNames())

                Worker.start(redis.uri, coreName).use { worker ->
                    assertEquals("READY hosting [double, square]", worker.ready, worker.output())
                    (0 until 200).forEach(numbers::publish)
                    assertEquals((0 until 200).map { it * 2 + 1 }, takeAll(output, 200, worker), worker.output())
                    assertEquals(49, declared.square.process(7), "a call of a chain hosted only by the worker")
                    assertEquals(0, worker.stop(), worker.output())
                    assertEquals("STOPPED", worker.lines.last(), worker.output())
                }

                val killed = Worker.start(redis.uri, coreName)
                killed.use { it.kill() }
                (200 until 300).forEach(numbers::publish)
                assertEquals(Optional.empty<Int>(), output.poll(), "nobody hosts 'double' now: the values wait")

                Worker.start(redis.uri, coreName).use { worker ->
                    assertEquals((200 until 300).map { it * 2 + 1 }, takeAll(output, 100, worker), worker.output())
                    assertEquals(0, worker.closeInput(), worker.output())
                }
                assertEquals(Optional.empty<Int>(), output.poll(), "no duplicates")
            }
        }
    }

    private fun takeAll(output: dev.prime.Reader<Int>, n: Int, worker: Worker): List<Int> = (0 until n).map { i ->
        output.take(Duration.ofSeconds(PATIENCE_S)).orElseThrow {
            AssertionError("value ${i + 1} of $n did not come back; worker output:\n${worker.output()}")
        }
    }

    /** A [RemoteWorkerMain] process; its output (stdout and stderr) is kept for failure messages. */
    private class Worker private constructor(private val process: Process) : AutoCloseable {
        val lines: MutableList<String> = Collections.synchronizedList(mutableListOf<String>())
        private val readyLine = CompletableFuture<String>()
        private val pump = thread(name = "two-process-test-worker-output", isDaemon = true) {
            try {
                process.inputStream.bufferedReader().useLines { all ->
                    all.forEach { line ->
                        lines += line
                        if (line.startsWith("READY")) readyLine.complete(line)
                    }
                }
            } catch (_: IOException) {
                // destroying the process closed its output: it ends here
            }
            readyLine.complete("(the worker ended without READY)")
        }

        val ready: String get() = readyLine.get(PATIENCE_S, TimeUnit.SECONDS)

        fun output(): String = synchronized(lines) { lines.joinToString("\n") }

        /** Sends STOP and returns the exit code. */
        fun stop(): Int {
            process.outputStream.write("STOP\n".toByteArray())
            process.outputStream.flush()
            return exitCode()
        }

        /** Closes the worker's input and returns the exit code. */
        fun closeInput(): Int {
            process.outputStream.close()
            return exitCode()
        }

        /** Kills the worker at once (SIGKILL), as a crash would. */
        fun kill() {
            process.destroyForcibly()
            check(process.waitFor(PATIENCE_S, TimeUnit.SECONDS)) { "the worker did not die" }
        }

        private fun exitCode(): Int {
            check(process.waitFor(PATIENCE_S, TimeUnit.SECONDS)) { "the worker did not stop; output:\n${output()}" }
            pump.join(TimeUnit.SECONDS.toMillis(PATIENCE_S))
            return process.exitValue()
        }

        override fun close() {
            process.destroyForcibly()
            process.waitFor(PATIENCE_S, TimeUnit.SECONDS)
            pump.join(TimeUnit.SECONDS.toMillis(PATIENCE_S))
        }

        companion object {
            fun start(redisUrl: String, coreName: String): Worker {
                val java = File(System.getProperty("java.home"), "bin/java").path
                val process = ProcessBuilder(
                    java, "-cp", System.getProperty("java.class.path"),
                    RemoteWorkerMain::class.java.name, redisUrl, coreName,
                ).redirectErrorStream(true).start()
                val worker = Worker(process)
                try {
                    check(worker.ready.startsWith("READY")) { "the worker did not start; output:\n${worker.output()}" }
                } catch (e: Throwable) {
                    worker.close()
                    throw e
                }
                return worker
            }
        }
    }

    private companion object {
        const val PATIENCE_S = 60L
    }
}

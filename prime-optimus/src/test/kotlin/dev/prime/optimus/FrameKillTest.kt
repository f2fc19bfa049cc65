package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.Source
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.Optional

/**
 * A frame survives a kill -9 of the JVM that was processing it: the worker took a frame of 256
 * values and stalled inside it (100 values done, nothing stored); it is killed with SIGKILL, a
 * copy of that frame is pushed again (as a publish retried after a lost reply would), and a
 * successor JVM takes over. Every value arrives once, in order; the successor ran its block on
 * exactly the 600 published values: the frame was redelivered whole, and its duplicate skipped
 * value by value.
 */
class FrameKillTest {

    @Test
    fun aFrameTakenByAKilledWorkerIsRedeliveredWholeWithNoLossAndNoDuplicates() {
        val name = "frame-kill"
        EmbeddedRedis.start().use { redis ->
            val config = CoreConfig.builder().name(name).sourceRetention(RETENTION).build()
            OptimusCore.builder().config(config).redis(redis.uri).hosts(emptyList()).leaseTime(Duration.ofSeconds(1)).build()
                .use { core ->
                    val (numbers, output) = declare(core) { it * 10 }.let { it.first to it.second.reader() }
                    core.start()
                    core.publishAll(numbers, (0 until VALUES).toList())
                    val keys = core.keys
                    val frame: ByteArray
                    WorkerProcess.start(FrameWorkerMain::class.java, redis.uri, name, "101").use { first ->
                        first.awaitLine("READY")
                        first.awaitLine("STALLED")
                        Jedis(URI(redis.uri)).use { raw ->
                            val held = raw.lrange(keys.serviceProcessing(SERVICE), 0, -1)
                            assertEquals(1, held.size, "the worker holds one entry")
                            frame = held.single()
                            assertEquals(256, Frame.count(frame), "a frame of 256 values")
                        }
                        first.kill()
                    }
                    Jedis(URI(redis.uri)).use { raw ->
                        assertEquals(256L, TestRedis.values(raw, keys.serviceProcessing(SERVICE)), "the frame waits whole")
                        raw.rpush(keys.serviceInput(SERVICE), frame) // the same 256 values delivered twice
                    }
                    assertEquals(Optional.empty<Int>(), output.poll(), "nothing of the stalled frame was stored")
                    WorkerProcess.start(FrameWorkerMain::class.java, redis.uri, name, "0").use { second ->
                        second.awaitLine("READY")
                        val received = (0 until VALUES).map { i ->
                            output.take(PATIENCE).orElseThrow { AssertionError("value $i did not arrive; worker:\n${second.output()}") }
                        }
                        assertEquals((0 until VALUES).map { it * 10 }, received, "0 lost, 0 reordered")
                        assertEquals(Optional.empty<Int>(), output.take(Duration.ofMillis(500)), "0 duplicated")
                        second.send("STOP")
                        assertEquals("PROCESSED $VALUES", second.awaitLine("PROCESSED"), "the duplicate frame was skipped")
                    }
                    Jedis(URI(redis.uri)).use { raw ->
                        assertEquals(0L, raw.llen(keys.serviceProcessing(SERVICE)) + raw.llen(keys.serviceInput(SERVICE)))
                    }
                }
        }
    }

    internal companion object {
        const val SERVICE = "times10"
        const val VALUES = 600
        const val RETENTION = 10_000
        val PATIENCE: Duration = Duration.ofSeconds(30)

        /** The topology both processes declare: source "numbers" → service [SERVICE] running [block]. */
        fun declare(core: OptimusCore, block: (Int) -> Int): Pair<Source<Int>, Source<Int>> {
            val numbers = core.source("numbers", EventBlock<Int>())
            return numbers to core.link(numbers, core.chain(SERVICE) { x: Int -> block(x) })
        }
    }
}

package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.Reader
import dev.prime.conformance.CapturedStderr
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import redis.clients.jedis.Jedis
import java.net.URI
import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.Files
import java.nio.file.Path
import java.time.Duration
import java.util.Optional

/**
 * Redis restarts empty (no persistence: everything it held is gone) under two live processes of
 * one topology. Each notices, counts it, and declares again what it hosts and reads, so every
 * value published after the restart reaches the services and readers.
 */
class RedisResetTest {

    @Test
    fun afterRedisRestartsEmptyEveryProcessRedeclaresAndEveryNewValueArrives() {
        val name = "redis-reset"
        val keys = Keys(name)
        val config = CoreConfig.builder().name(name).build()
        val err = CapturedStderr()
        err.use { EmbeddedRedis.start().use { redis ->
            fun core(vararg hosts: String) =
                OptimusCore.builder().config(config).redis(redis.uri).leaseTime(LEASE).hosts(*hosts).build()
            val events = EventBlock<Int>()
            core("double", "square").use { host ->
                core().use { other ->
                    val numbers = host.source("numbers", events)
                    val direct = numbers.reader()
                    val outputReader = numbers.then(host.chain("double") { x: Int -> 2 * x }).reader()
                    val square = host.chain("square") { x: Int -> x * x }.toBlock()
                    // the other process declares the same topology, hosts nothing and reads the output
                    val otherOutput = other.source("numbers", EventBlock<Int>()).then(other.chain("double") { x: Int -> 2 * x }).reader()
                    other.chain("square") { x: Int -> x * x }.toBlock()
                    host.start()
                    other.start()

                    (0 until 100).forEach(events::publish)
                    assertEquals((0 until 100).toList(), takeAll(direct, 100))
                    assertEquals((0 until 100).map { 2 * it }, takeAll(outputReader, 100))
                    assertEquals((0 until 100).map { 2 * it }, takeAll(otherOutput, 100))
                    assertEquals(49, square.process(7))
                    val hostLease = Jedis(URI(redis.uri)).use { it.get(keys.hostLease("double").toString(UTF_8)) }
                    assertEquals(0L, host.redisResets())

                    redis.kill()
                    redis.restart() // empty: no persistence

                    (100 until 300).forEach(events::publish)
                    assertEquals((100 until 300).toList(), takeAll(direct, 200), "a reader of the source")
                    assertEquals((100 until 300).map { 2 * it }, takeAll(outputReader, 200), "a service fed by the source")
                    assertEquals((100 until 300).map { 2 * it }, takeAll(otherOutput, 200), "a reader in the other process")
                    assertEquals(64, square.process(8), "a synchronous call")
                    assertEquals(Optional.empty<Int>(), direct.poll(), "no duplicates")
                    assertEquals(Optional.empty<Int>(), outputReader.poll(), "no duplicates")
                    assertEquals(1L, host.redisResets(), "the host counted the reset")
                    assertEquals(1L, other.redisResets(), "the other process counted it too")
                    Jedis(URI(redis.uri)).use { jedis ->
                        assertEquals(hostLease, jedis.get(keys.hostLease("double").toString(UTF_8)), "the host lease is declared again")
                        assertEquals(KryoCodec.standard().fingerprint(), jedis.get(keys.codec.toString(UTF_8)), "the codec fingerprint too")
                        assertEquals(2L, jedis.scard(keys.instances), "both instances are registered again")
                    }
                    // redisResets(): "each time the core logged a WARN and declared again what it hosts and reads"
                    val warnings = err.lines().filter { "Redis lost the data of topology '$name'" in it }
                    assertEquals(2, warnings.size, "one WARN per process: $warnings")
                    assertTrue(warnings.all { " WARN " in it && "re-declares" in it }, "$warnings")
                }
            }
        } }
    }

    /**
     * Redis comes back behind this process (as after a failover to a replica that lagged, or a
     * crash with `appendfsync everysec`): it has the topology's data, but not a reader registered
     * last. The process notices that Redis holds fewer of its declarations than it made.
     */
    @Test
    fun redisThatComesBackBehindIsNoticedAndTheMissingRegistrationDeclaredAgain(@TempDir dir: Path) {
        val config = CoreConfig.builder().name("redis-behind").build()
        EmbeddedRedis.builder().appendOnlyDir(dir).start().use { redis ->
            // a lease long enough to outlive the stale copy: only the declaration count can tell
            OptimusCore.builder().config(config).redis(redis.uri).leaseTime(Duration.ofSeconds(6)).build().use { core ->
                val events = EventBlock<Int>()
                val numbers = core.source("numbers", events)
                val early = numbers.reader()
                core.start()
                events.publish(0)
                assertEquals(listOf(0), takeAll(early, 1))

                val aof = dir.resolve("appendonlydir")
                val stale = dir.resolve("stale")
                copyTree(aof, stale) // what a lagging replica would have
                val late = numbers.reader() // registered after the copy

                redis.kill()
                deleteTree(aof)
                Files.move(stale, aof)
                redis.restart()

                (1 until 101).forEach(events::publish)
                assertEquals((1 until 101).toList(), takeAll(early, 100), "the reader Redis still knew")
                assertEquals((0 until 101).toList(), takeAll(late, 101), "the reader Redis had lost, declared again")
                assertEquals(1L, core.redisResets())
            }
        }
    }

    private fun copyTree(from: Path, to: Path) {
        Files.createDirectories(to)
        Files.list(from).use { files -> files.forEach { Files.copy(it, to.resolve(it.fileName)) } }
    }

    private fun deleteTree(dir: Path) {
        Files.list(dir).use { files -> files.forEach(Files::delete) }
        Files.delete(dir)
    }

    private fun <T> takeAll(reader: Reader<T>, n: Int): List<T> = (0 until n).map { i ->
        reader.take(PATIENCE).orElseThrow { AssertionError("value ${i + 1} of $n did not arrive within $PATIENCE") }
    }

    private companion object {
        val LEASE: Duration = Duration.ofSeconds(1)
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

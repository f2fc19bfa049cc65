package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.Reader
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration
import java.util.Optional
import java.util.concurrent.ConcurrentHashMap
import java.util.concurrent.atomic.AtomicInteger

/**
 * README, "Nothing is done twice": a service and a reader skip an id they handled recently, so an
 * entry that reaches them again (a push retried after a lost reply) is processed and delivered once.
 */
class DuplicateIdTest {

    @Test
    fun aServiceSkipsAnIdItHandledRecently() {
        val runs = ConcurrentHashMap<Int, AtomicInteger>()
        core("duplicate-service").use { core ->
            val output = core.source("numbers", EventBlock<Int>()).then(core.chain("count") { x: Int ->
                runs.computeIfAbsent(x) { AtomicInteger() }.incrementAndGet()
                x
            }).reader()
            core.start()
            Jedis(URI(TestRedis.url)).use { raw ->
                val input = core.keys.serviceInput("count")
                val first = Envelope.value(42L, core.encode(1))
                raw.rpush(input, first)
                assertEquals(Optional.of(1), output.take(PATIENCE))
                // the same entry again (as a retried push leaves it), then a new one behind it
                raw.rpush(input, first, Envelope.value(43L, core.encode(2)))
                assertEquals(Optional.of(2), output.take(PATIENCE), "the repeated id is skipped, the next value comes")
            }
            assertEquals(1, runs[1]?.get(), "the block ran once for the id that came twice: $runs")
            assertEquals(1, runs[2]?.get(), "$runs")
        }
    }

    @Test
    fun aReaderSkipsAnIdItDeliveredRecently() {
        core("duplicate-reader").use { core ->
            val reader: Reader<Int> = core.source("numbers", EventBlock<Int>()).reader()
            core.start()
            Jedis(URI(TestRedis.url)).use { raw ->
                val list = raw.smembers(core.keys.sourceReaders("numbers")).single { ":rdr:" in it.toString(UTF_8) }
                val first = Envelope.value(44L, core.encode(7))
                raw.rpush(list, first)
                assertEquals(Optional.of(7), reader.take(PATIENCE))
                raw.rpush(list, first, Envelope.value(45L, core.encode(8)))
                assertEquals(Optional.of(8), reader.take(PATIENCE), "the repeated id is skipped, the next value comes")
            }
        }
    }

    private fun core(name: String): OptimusCore = OptimusCore.builder()
        .config(CoreConfig.builder().name("$name-${System.nanoTime()}").build())
        .redis(TestRedis.url)
        .build()

    private companion object {
        val PATIENCE: Duration = Duration.ofSeconds(10)
    }
}

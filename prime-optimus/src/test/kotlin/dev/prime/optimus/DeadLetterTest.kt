package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.conformance.CapturedStderr
import dev.prime.EventBlock
import dev.prime.ErrorHandler
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.concurrent.CopyOnWriteArrayList

/** Bad bytes and failing blocks: dead letters with a reason, and the service goes on. */
class DeadLetterTest {

    @Test
    fun undecodableBytesGoToTheDeadLettersAndTheServiceGoesOn() {
        TestRedis.core().use { core ->
            val events = EventBlock<Int>()
            val out = core.source("numbers", events).then(core.chain("increment") { x: Int -> x + 1 }).reader()
            core.start()
            Jedis(URI(TestRedis.url)).use { raw ->
                val input = core.keys.serviceInput("increment")
                raw.rpush(input, "not an envelope".toByteArray())
                raw.rpush(input, Envelope.value(1L, byteArrayOf(-1, -2, -3, -4, -5)))
            }
            events.publish(41)
            assertEquals(42, out.take(PATIENCE).orElseThrow())
            val letters = core.deadLetters("increment")
            assertEquals(2, letters.size, letters.toString())
            assertTrue(letters[0].reason.contains("undecodable envelope"), letters[0].reason)
            assertEquals("not an envelope", String(letters[0].bytes()))
            assertTrue(letters[1].reason.contains("cannot decode the value"), letters[1].reason)
            assertEquals(2, core.clearDeadLetters("increment"))
            assertEquals(listOf<DeadLetter>(), core.deadLetters("increment"))
        }
    }

    @Test
    fun aBurstOfDeadLettersIsLoggedOnceThenCountedAndTheCountWrittenAtClose() {
        val lines = CapturedStderr().use { err ->
            TestRedis.core().use { core ->
                val events = EventBlock<Int>()
                val out = core.source("bursty", events).then(core.chain("burst-target") { x: Int -> x + 1 }).reader()
                core.start()
                Jedis(URI(TestRedis.url)).use { raw ->
                    val input = core.keys.serviceInput("burst-target")
                    repeat(100) { raw.rpush(input, "garbage $it".toByteArray()) }
                }
                events.publish(41) // behind the 100 bad entries: once it is out, they were handled
                assertEquals(42, out.take(PATIENCE).orElseThrow())
                assertEquals(100, core.deadLetters("burst-target").size)
            }
            err.lines().filter { it.contains("service 'burst-target' dead-lettered") }
        }
        assertTrue(lines.size in 2..3, "one WARN line, then a summary or two (the last at close), not ${lines.size}: $lines")
        assertTrue(lines[0].contains(" WARN ") && lines[0].contains("undecodable envelope"), lines[0])
        // the first line is one entry; the summaries count the rest, the last one written at close
        val summarised = lines.drop(1).sumOf { Regex("(\\d+) more in the last").find(it)!!.groupValues[1].toLong() }
        assertEquals(99L, summarised, "the lines count every dead letter: $lines")
    }

    @Test
    fun failingValueIsRetriedThenReportedAndDeadLettered() {
        val reported = CopyOnWriteArrayList<Any>()
        val handler = ErrorHandler { _, input, _ -> reported += input }
        val attempts = HashMap<Int, Int>()
        OptimusCore.builder()
            .config(CoreConfig.builder().errorHandler(handler).build())
            .redis(TestRedis.url)
            .retries(2)
            .build().use { core ->
                val events = EventBlock<Int>()
                val flaky = core.chain("flaky") { x: Int ->
                    val n = attempts.merge(x, 1, Int::plus)!!
                    // 1 succeeds on its third attempt; 2 never does
                    if (x == 2 || (x == 1 && n < 3)) throw IllegalStateException("attempt $n of $x")
                    x * 10
                }
                val out = core.source(events).then(flaky).reader()
                core.start()
                events.publish(1)
                events.publish(2)
                events.publish(3)
                assertEquals(10, out.take(PATIENCE).orElseThrow())
                assertEquals(30, out.take(PATIENCE).orElseThrow())
                assertEquals(listOf<Any>(2), reported)
                assertEquals(3, attempts[2])
                val letters = core.deadLetters("flaky")
                assertEquals(1, letters.size)
                assertTrue(letters[0].reason.startsWith("failed after 3 attempt(s)"), letters[0].reason)
                assertTrue(letters[0].reason.contains("attempt 3 of 2"), letters[0].reason)
            }
    }

    private companion object {
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

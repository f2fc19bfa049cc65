package dev.prime.optimus

import dev.prime.EventBlock
import dev.prime.Reader
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration

/**
 * Crafted entries cannot stop a service or make it write outside its namespace: a request whose
 * reply key is another key of the topology, a key outside it, or a key of the wrong type is
 * dead-lettered with the reason; a step that Redis refuses (WRONGTYPE on the next service's input)
 * dead-letters the entries it could not store, one by one, and the service goes on.
 */
class PoisonEntryTest {

    @Test
    fun requestsWithForeignReplyKeysAreDeadLetteredAndTheServiceKeepsServing() {
        OptimusCore.builder().redis(TestRedis.url).callTimeout(Duration.ofSeconds(20)).build().use { core ->
            val echo = core.chain("echo") { x: Int -> x }.toBlock()
            core.start()
            val payload = core.encode(7)
            val wrongKind = core.keys.reply("not-a-list")
            Jedis(URI(TestRedis.url)).use { raw ->
                raw.set(wrongKind, "a string".toByteArray())
                val input = core.keys.serviceInput("echo")
                raw.rpush(input, Envelope.request(1L, core.keys.codec, payload))
                raw.rpush(input, Envelope.request(2L, "victim:list".toByteArray(UTF_8), payload))
                raw.rpush(input, Envelope.request(3L, wrongKind, payload))
                assertEquals(5, echo.process(5), "the service still serves")
                assertFalse(raw.exists("victim:list"), "nothing was written outside the namespace")
                assertEquals("string", raw.type(core.keys.codec))
                assertEquals("string", raw.type(wrongKind))
            }
            val reasons = core.deadLetters("echo").map { it.reason }
            assertEquals(3, reasons.size, reasons.toString())
            assertTrue(reasons.all { "reply key" in it }, reasons.toString())
            assertTrue("victim:list" in reasons[1], reasons[1])
        }
    }

    @Test
    fun aStepRedisRefusesDeadLettersItsEntriesAndTheServiceGoesOn() {
        OptimusCore.builder().redis(TestRedis.url).build().use { core ->
            val (events, out) = twoServices(core)
            core.start()
            val nextInput = core.keys.serviceInput("second")
            Jedis(URI(TestRedis.url)).use { raw ->
                raw.set(nextInput, "not a list".toByteArray())
                events.publish(1)
                events.publish(2)
                events.publish(3)
                val deadline = System.nanoTime() + PATIENCE.toNanos()
                while (core.deadLetters("first").size < 3 && System.nanoTime() < deadline) Thread.sleep(20)
                val reasons = core.deadLetters("first").map { it.reason }
                assertEquals(3, reasons.size, reasons.toString())
                assertTrue(reasons.all { "WRONGTYPE" in it }, reasons.toString())
                raw.del(nextInput)
            }
            events.publish(10)
            assertEquals(22, out.take(PATIENCE).orElseThrow(), "the service goes on once its next input is a list again")
        }
    }

    @Test
    fun anEntryWhoseResultsAndDeadLetterRedisBothRefusesIsDroppedAndTheServiceGoesOn() {
        OptimusCore.builder().redis(TestRedis.url).build().use { core ->
            val (events, out) = twoServices(core)
            core.start()
            val nextInput = core.keys.serviceInput("second")
            val deadLetters = core.keys.deadLetters("first")
            val processing = core.keys.serviceProcessing("first")
            Jedis(URI(TestRedis.url)).use { raw ->
                raw.set(nextInput, "not a list".toByteArray())
                raw.set(deadLetters, "not a list either".toByteArray())
                events.publish(1)
                events.publish(2)
                // the service is past both values once its input and processing list are empty
                val deadline = System.nanoTime() + PATIENCE.toNanos()
                while ((raw.llen(core.keys.serviceInput("first")) > 0 || raw.llen(processing) > 0) &&
                    System.nanoTime() < deadline
                ) Thread.sleep(20)
                assertEquals(0, raw.llen(core.keys.serviceInput("first")), "values left in the input")
                assertEquals(0, raw.llen(processing), "entries left in the processing list")
                assertEquals("not a list either", String(raw.get(deadLetters), UTF_8), "the dead-letter key was overwritten")
                raw.del(nextInput, deadLetters)
            }
            events.publish(10)
            assertEquals(22, out.take(PATIENCE).orElseThrow(), "the service goes on once its keys are lists again")
            assertEquals(0, core.deadLetters("first").size, "the dropped entries were not dead-lettered")
        }
    }

    /** Source "numbers" → service "first" (x + 1) → service "second" (x × 2); the event block and a reader of the output. */
    private fun twoServices(core: OptimusCore): Pair<EventBlock<Int>, Reader<Int>> {
        val events = EventBlock<Int>()
        val out = core.source("numbers", events)
            .then(core.chain("first") { x: Int -> x + 1 }.then(core.chain("second") { x: Int -> x * 2 })).reader()
        return events to out
    }

    private companion object {
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

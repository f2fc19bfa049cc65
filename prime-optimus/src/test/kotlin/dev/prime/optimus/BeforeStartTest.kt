package dev.prime.optimus

import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration

/** Calls and reads before start() fail at once and say so, instead of waiting for a service that never starts. */
class BeforeStartTest {

    @Test
    fun aCallBeforeStartFailsAtOnceNamingTheChainAndTheCore() {
        TestRedis.core().use { core ->
            val call = core.chain("early") { x: Int -> x + 1 }.toBlock()
            val started = System.nanoTime()
            val e = assertThrows(IllegalStateException::class.java) { call.process(1) }
            val took = Duration.ofNanos(System.nanoTime() - started)
            assertTrue(took < Duration.ofSeconds(1), "failed after $took")
            for (word in listOf("start()", "'early'", "'${core.name()}'")) assertTrue(e.message!!.contains(word), e.message)
            core.start()
            assertEquals(2, call.process(1), "works once started")
        }
    }

    @Test
    fun publishingBeforeStartFailsAtOnceAndPublishesNothing() {
        TestRedis.core().use { core ->
            val events = EventBlock<Int>()
            val source = core.source("early-publish", events)
            val reader = source.reader()
            for (publish in listOf({ events.publish(1) }, { core.publishAll(source, listOf(2, 3)) })) {
                val e = assertThrows(IllegalStateException::class.java) { publish() }
                assertTrue(e.message!!.contains("start()") && e.message!!.contains(core.name()), e.message)
            }
            core.start()
            events.publish(4)
            assertEquals(listOf(4), listOf(reader.take(Duration.ofSeconds(20)).orElseThrow()) + reader.drain())
        }
    }

    @Test
    fun readingAnOptimusSourceBeforeStartFailsAtOnce() {
        TestRedis.core().use { core ->
            val events = EventBlock<Int>()
            val reader = core.source("early-source", events).reader()
            val started = System.nanoTime()
            for (read in listOf({ reader.take(Duration.ofSeconds(5)) }, { reader.poll() }, { reader.drain() }, { reader.take() })) {
                val e = assertThrows(IllegalStateException::class.java) { read() }
                assertTrue(e.message!!.contains("start()") && e.message!!.contains(core.name()), e.message)
            }
            val took = Duration.ofNanos(System.nanoTime() - started)
            assertTrue(took < Duration.ofSeconds(1), "failed after $took")
            core.start()
            events.publish(7)
            assertEquals(7, reader.take(Duration.ofSeconds(20)).orElseThrow())
        }
    }
}

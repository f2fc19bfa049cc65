package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration

/**
 * A topology lives in Redis, not in a core, as the README's "Several processes" says: a core
 * started later under the same name on the same Redis processes what waits in its services'
 * inputs, and `close()` removes only the core's own readers, reply lists and leases, so source
 * logs and dead letters stay. (That its readers first get what the source logs retain is a kit
 * test on every media:
 * `LifecycleConformance.aCoreUnderTheNameOfAClosedOneStartsEmptyOrCarriesOnAsItsMediaSays`.)
 */
class TopologyOutlivesItsCoresTest {
    private val patience = Duration.ofSeconds(20)

    private fun core(name: String, hosts: List<String>? = null): OptimusCore {
        val builder = OptimusCore.builder().config(CoreConfig.builder().name(name).build()).redis(TestRedis.url)
        if (hosts != null) builder.hosts(hosts)
        return builder.build()
    }

    @Test
    fun valuesWaitingInAServicesInputAreProcessedByALaterCore() {
        val name = "outlives-input-${System.nanoTime()}"
        core(name, hosts = emptyList()).use { first -> // hosts nothing: "double" has no host yet
            val events = EventBlock<Int>()
            first.source("numbers", events).then(first.chain("double") { x: Int -> 2 * x })
            first.start()
            for (i in 1..3) events.publish(i)
        }
        core(name).use { second -> // hosts everything
            val events = EventBlock<Int>()
            val doubled = second.source("numbers", events).then(second.chain("double") { x: Int -> 2 * x })
            val reader = doubled.reader()
            second.start()
            val got = (1..3).map { reader.take(patience).orElseThrow { AssertionError("only ${it - 1} values came") } }
            assertEquals(listOf(2, 4, 6), got, "what waited in double's input, processed by the later core")
        }
    }

    /**
     * `close()` removes only the core's own readers, reply lists and leases: a source's log and a
     * service's dead letters stay in Redis, and a later core of the name reads those dead letters.
     */
    @Test
    fun closeRemovesTheCoresReadersReplyListsAndLeasesAndLeavesLogsAndDeadLetters() {
        val name = "outlives-close-${System.nanoTime()}"
        val keys = Keys(name)
        val config = CoreConfig.builder().name(name).errorHandler { _, _, _ -> }.build()
        OptimusCore.builder().config(config).redis(TestRedis.url).build().use { first ->
            val events = EventBlock<Int>()
            val numbers = first.source("numbers", events)
            val reader = numbers.reader()
            val picked = numbers.then(first.chain("picky") { x: Int -> require(x >= 0) { "negative: $x" }; x }).reader()
            val echo = first.chain("echo") { x: Int -> x }.toBlock()
            first.start()
            events.publish(-1)
            events.publish(2)
            assertEquals(listOf(-1, 2), List(2) { reader.take(patience).orElseThrow() })
            // picky stores -1's dead letter in the step that handles it, before or with 2's output
            assertEquals(2, picked.take(patience).orElseThrow(), "picky's value after the failed one")
            assertEquals(1, first.deadLetters("picky").size, "picky's dead letter")
            assertEquals(7, echo.process(7))
            Jedis(URI(TestRedis.url)).use { raw ->
                val open = TestRedis.keysOf(raw, name)
                assertTrue(open.any { it.contains(":rdr:") }, "a reader list while the core is open: $open")
                assertTrue(open.any { it.contains(":reply:") }, "a reply list while the core is open: $open")
                assertTrue(raw.exists(keys.hostLease("picky")), "picky's host lease while the core is open: $open")
            }
        }
        Jedis(URI(TestRedis.url)).use { raw ->
            val left = TestRedis.keysOf(raw, name)
            assertEquals(listOf<String>(), left.filter { ":rdr:" in it || ":reply:" in it }, "reader and reply lists left: $left")
            assertFalse(raw.exists(keys.hostLease("picky")), "picky's host lease left: $left")
            assertFalse(raw.exists(keys.hostLease("echo")), "echo's host lease left: $left")
            assertEquals(2L, TestRedis.values(raw, keys.sourceLog("numbers")), "the source's log stays: $left")
            assertEquals(1L, raw.llen(keys.deadLetters("picky")), "picky's dead letters stay: $left")
        }
        core(name).use { later ->
            assertEquals(1, later.deadLetters("picky").size, "a later core reads the dead letter")
        }
    }
}

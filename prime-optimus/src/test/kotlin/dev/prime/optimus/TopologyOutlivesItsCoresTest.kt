package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import java.time.Duration
import java.util.Optional

/**
 * A topology lives in Redis, not in a core, as the README's "Several processes" says: a core
 * started later under the same name on the same Redis carries on where the closed one stopped.
 */
class TopologyOutlivesItsCoresTest {
    private val patience = Duration.ofSeconds(20)

    private fun core(name: String, hosts: List<String>? = null): OptimusCore {
        val builder = OptimusCore.builder().config(CoreConfig.builder().name(name).build()).redis(TestRedis.url)
        if (hosts != null) builder.hosts(hosts)
        return builder.build()
    }

    @Test
    fun aReaderOfALaterCoreFirstGetsWhatTheSourceRetainedFromTheEarlierOne() {
        val name = "outlives-log-${System.nanoTime()}"
        core(name).use { first ->
            val events = EventBlock<Int>()
            first.source("numbers", events)
            first.start()
            for (i in 1..3) events.publish(i)
        }
        core(name).use { second ->
            val events = EventBlock<Int>()
            val reader = second.source("numbers", events).reader()
            second.start()
            events.publish(4)
            val got = (1..4).map { reader.take(patience).orElseThrow { AssertionError("only ${it - 1} values came") } }
            assertEquals(listOf(1, 2, 3, 4), got, "the earlier core's values, retained in the source's log, then the new one")
            assertEquals(Optional.empty<Int>(), reader.take(Duration.ofMillis(200)), "nothing more")
        }
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
}

package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import java.time.Duration

/**
 * A topology lives in Redis, not in a core, as the README's "Several processes" says: a core
 * started later under the same name on the same Redis processes what waits in its services'
 * inputs. (That its readers first get what the source logs retain is a kit test on every media:
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
}

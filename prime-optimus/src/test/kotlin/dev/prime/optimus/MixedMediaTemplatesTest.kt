package dev.prime.optimus

import dev.prime.ChainFailedException
import dev.prime.EventBlock
import dev.prime.Token
import dev.prime.Tuple2
import dev.prime.liberty.LibertyCore
import dev.prime.radiant.RadiantCore
import dev.prime.topology.TopologyNode
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertSame
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.assertThrows
import java.time.Duration

/**
 * The paper's mixed topology (architecture.md, "Media can be mixed"): chains of an Optimus core
 * run as Optimus services while the chain that links them, or the template that chooses between
 * them, is a local Liberty or Radiant chain; and the other way round.
 */
class MixedMediaTemplatesTest {

    @Test
    fun libertyAndRadiantTemplatesTakeOptimusChainsWhichRunAsOptimusServices() {
        LibertyCore().use { liberty ->
            RadiantCore().use { radiant ->
                TestRedis.core().use { optimus ->
                    val linked = liberty.link(
                        optimus.chain("plus-one") { x: Int -> x + 1 },
                        optimus.chain("times-ten") { x: Int -> x * 10 },
                    ).toBlock()
                    val chosen = liberty.ifThenElse(
                        { x: Int -> x > 0 },
                        optimus.chain("positive") { x: Int -> "+$x" },
                        optimus.chain("not-positive") { x: Int -> "-$x" },
                    ).toBlock()
                    val both = radiant.union(
                        optimus.chain("halve") { x: Int -> x / 2 },
                        optimus.chain("square") { x: Int -> x * x },
                    ).toBlock()
                    val guarded = radiant.guard(
                        { x: Int -> x < 100 },
                        optimus.chain("small") { x: Int -> x + 1000 },
                        { _: Int -> -1 },
                    ).toBlock()
                    optimus.start()

                    assertEquals(50, linked.process(4))
                    assertEquals("+3", chosen.process(3))
                    assertEquals("-0", chosen.process(0))
                    assertEquals(Tuple2(3, 49), both.process(7))
                    assertEquals(1005, guarded.process(5))
                    assertEquals(-1, guarded.process(500))
                    assertEquals(
                        setOf("plus-one", "times-ten", "positive", "not-positive", "halve", "square", "small"),
                        optimus.serviceNames(),
                        "every Optimus chain given to another core's template is an Optimus service",
                    )
                    val foreign = liberty.topology().nodes().filterIsInstance<TopologyNode.ForeignChain>()
                        .map { it.name() }.toSet()
                    assertTrue(foreign.containsAll(setOf("hosted(plus-one)", "hosted(positive)")), "$foreign")
                }
            }
        }
    }

    @Test
    fun anOptimusTemplateTakesLibertyAndRadiantChainsAndAFailureNamesTheirChain() {
        LibertyCore().use { liberty ->
            RadiantCore().use { radiant ->
                TestRedis.core().use { optimus ->
                    val chosen = optimus.ifThenElse(
                        { x: Int -> x % 2 == 0 },
                        liberty.chain("even") { x: Int -> x / 2 },
                        radiant.chain("odd") { x: Int -> if (x < 0) throw IllegalStateException("negative $x") else 3 * x + 1 },
                    ).toBlock()
                    optimus.start()
                    assertEquals(5, chosen.process(10))
                    assertEquals(22, chosen.process(7))
                    val failed = assertThrows<ChainFailedException> { chosen.process(-3) }
                    assertTrue(failed.message!!.contains("odd"), "names the Radiant chain: ${failed.message}")
                }
            }
        }
    }

    @Test
    fun aSourceOfOneMediaFeedsServicesAndCollectorsOfAnother() {
        LibertyCore().use { liberty ->
            TestRedis.core().use { optimus ->
                val events = EventBlock<Int>()
                val libertySource = liberty.source("ticks", events)
                // a Liberty source linked to an Optimus chain: the Optimus chain's service
                val out = libertySource.then(optimus.chain("doubled") { x: Int -> 2 * x }).reader()
                val optimusEvents = EventBlock<String>()
                val optimusSource = optimus.source("words", optimusEvents)
                val next = liberty.syncCollector(optimusSource).toBlock()
                liberty.start()
                optimus.start()

                events.publish(21)
                assertEquals(42, out.take(PATIENCE).orElseThrow())
                optimusEvents.publish("hello")
                assertEquals("hello", next.process(Token.INSTANCE))
                assertSame(liberty, libertySource.core())
            }
        }
    }

    private companion object {
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

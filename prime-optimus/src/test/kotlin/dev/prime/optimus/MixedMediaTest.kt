package dev.prime.optimus

import dev.prime.Block
import dev.prime.EventBlock
import dev.prime.liberty.LibertyCore
import dev.prime.radiant.RadiantCore
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import java.time.Duration

/** Any block goes into any core: fused chains as Optimus services, Optimus calls inside fused chains. */
class MixedMediaTest {

    @Test
    fun fusedLibertyAndRadiantChainsRunAsOneOptimusServiceEach() {
        LibertyCore().use { liberty ->
            RadiantCore().use { radiant ->
                TestRedis.core().use { optimus ->
                    val fusedByLiberty: Block<Int, Int> =
                        liberty.chain { x: Int -> x + 1 }.then(liberty.chain { x: Int -> x * 10 }).toBlock()
                    val fusedByRadiant: Block<Int, Int> =
                        radiant.chain { x: Int -> x - 3 }.then(radiant.chain { x: Int -> x * x }).toBlock()
                    val events = EventBlock<Int>()
                    val out = optimus.source(events)
                        .then(optimus.chain("liberty-part", fusedByLiberty))
                        .reader()
                    val call = optimus.chain("radiant-part", fusedByRadiant).toBlock()
                    optimus.start()
                    events.publish(4)
                    assertEquals(50, out.take(PATIENCE).orElseThrow())
                    assertEquals(16, call.process(7))
                    assertEquals(setOf("numbers>liberty-part", "radiant-part").size, optimus.serviceNames().size)
                }
            }
        }
    }

    @Test
    fun optimusChainInsideALibertyChainAndALibertyChainLinkedToAnOptimusSource() {
        LibertyCore().use { liberty ->
            TestRedis.core().use { optimus ->
                val remoteSquare = optimus.chain("square") { x: Int -> x * x }.toBlock()
                optimus.start()
                val local = liberty.chain { x: Int -> x + 1 }.then(liberty.chain(remoteSquare)).toBlock()
                assertEquals(25, local.process(4))

                val events = EventBlock<Int>()
                val source = optimus.source(events)
                // a chain of another core linked to an Optimus source runs as an Optimus service
                val out = source.then(liberty.chain { x: Int -> -x }).reader()
                events.publish(9)
                assertEquals(-9, out.take(PATIENCE).orElseThrow())
            }
        }
    }

    private companion object {
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

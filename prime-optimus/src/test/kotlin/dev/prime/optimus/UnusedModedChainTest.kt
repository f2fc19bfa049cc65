package dev.prime.optimus

import dev.prime.Block
import dev.prime.CoreConfig
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration

/**
 * `start()` refuses a hosting mode for a chain that nothing in this process used by then (its
 * service does not run), saying so and how to fix it; a mode for a timer is refused as before, as
 * a service that is not a chain's.
 */
class UnusedModedChainTest {

    @Test
    fun aModedChainNothingUsedByStartIsRefusedSayingItIsUnusedAndHowToFixIt() {
        val core = core("planner", Hosting.ORDERED)
        core.use {
            core.chain("planner", Block<Int, Int> { it + 1 }) // declared, never used before start()
            core.chain("odometry", Block<Int, Int> { it * 2 }).toBlock()
            val refused = assertThrows(IllegalArgumentException::class.java) { core.start() }
            val message = refused.message!!
            assertTrue("chain 'planner' (Hosting.ORDERED)" in message, message)
            assertTrue("no chain of this process has used by start()" in message, message)
            assertTrue("Use the chain before start()" in message && "remove hosting(...)" in message, message)
            assertFalse("combinators, timers or generic services" in message, "not a combinator, timer or generic service: $message")
        }
    }

    @Test
    fun aModeForATimerIsStillRefusedAsNotAChainsService() {
        val core = core("tick", Hosting.UNORDERED)
        core.use {
            core.timer("tick", Duration.ofSeconds(1))
            val refused = assertThrows(IllegalArgumentException::class.java) { core.start() }
            assertTrue("combinators, timers or generic services" in refused.message!!, refused.message)
        }
    }

    private fun core(service: String, hosting: Hosting): OptimusCore =
        OptimusCore.builder().config(CoreConfig.builder().name("unused-moded-${System.nanoTime()}").build())
            .redis(TestRedis.url).hosting(service, hosting).build()
}

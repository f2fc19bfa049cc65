package dev.prime.optimus

import dev.prime.Block
import dev.prime.CoreConfig
import dev.prime.ChainFailedException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertInstanceOf
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration
import java.util.concurrent.atomic.AtomicReference

/**
 * A block of an isolated chain that calls the same isolated chain through another user
 * ([SelfCalls]): refused at once where the call is made on the thread of the chain's service,
 * wherever the users run, and where it is made on another service's thread, for a call that the
 * chain's service waits for in the same process.
 */
class IsolatedSelfCallTest {

    /**
     * The users run in one process, the isolated chain's service in another: the block's call is
     * made in the process that runs the chain's service, which refuses it at once; the caller's
     * process gets the failure's text.
     */
    @Test
    fun aCallFromInsideItselfIsRefusedWhereTheIsolatedChainRunsWhereverItsUsersRun() {
        val config = named()
        OptimusCore.builder().config(config).redis(TestRedis.url).hosts("counter@1", "counter@2").build().use { users ->
            OptimusCore.builder().config(config).redis(TestRedis.url).hosts("counter").build().use { shared ->
                val (outer, _) = users.counter()
                shared.counter()
                users.start()
                shared.start()
                assertRefusedFromInsideItselfInAnotherProcess(outer, reentering = 1)
            }
        }
    }

    /**
     * The isolated chain's block calls another chain, whose block calls the isolated chain: that
     * call runs on the other chain's service thread, but the isolated chain's service, which waits
     * for it in this process, is on its path ([CallPaths]): it is refused at once, not by the call
     * timeout (60 s here), and the isolated chain then serves the next call.
     */
    @Test
    fun aCallFromInsideItselfThroughAnotherServiceIsRefusedAtOnce() {
        TestRedis.core(named()).use { core ->
            val user = AtomicReference<Block<Int, Int>>()
            val relay = core.chain("relay") { x: Int -> user.get().process(x) }.toBlock()
            val isolated = core.isolate(core.chain("counter") { x: Int -> if (x > 0) relay.process(x - 1) + 1 else 0 })
            val outer = isolated.newUser().toBlock()
            user.set(isolated.newUser().toBlock())
            core.start()
            val began = System.nanoTime()
            val failure = assertThrows(ChainFailedException::class.java) { outer.process(1) }
            val took = Duration.ofNanos(System.nanoTime() - began)
            assertTrue(took < Duration.ofSeconds(10), "refused at once, not by the call timeout of 60 s: after $took")
            val refusal = assertInstanceOf(IllegalStateException::class.java, failure.cause, failure.toString())
            assertTrue("isolated chain 'counter' was called from inside itself" in refusal.message!!, refusal.message)
            assertEquals(0, outer.process(0), "the isolated chain serves the next call")
        }
    }

    /** The kit's re-entering counter, declared in [this] core: its two users' blocks. */
    private fun OptimusCore.counter(): Pair<Block<Int, Int>, Block<Int, Int>> {
        val inner = AtomicReference<Block<Int, Int>>()
        val isolated = isolate(chain("counter") { x: Int -> if (x > 0) inner.get().process(x - 1) + 1 else 0 })
        val outer = isolated.newUser().toBlock()
        inner.set(isolated.newUser().toBlock())
        return outer to inner.get()
    }

    private fun named(): CoreConfig = CoreConfig.builder().name("self-call-${System.nanoTime()}").build()
}

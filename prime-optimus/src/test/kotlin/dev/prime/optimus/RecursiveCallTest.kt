package dev.prime.optimus

import dev.prime.Block
import dev.prime.CoreConfig
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration
import java.util.concurrent.atomic.AtomicReference

/**
 * A chain whose block calls its own chain: each service takes one request at a time, so the
 * call would wait for itself. It is refused at once where it is made, on the thread of the
 * chain's service (the kit checks it in one process); a service given [Hosting.UNORDERED] is
 * not refused, since another host may take the call.
 */
class RecursiveCallTest {

    /** The caller runs in one process, the chain's service in another, which refuses the call. */
    @Test
    fun aChainThatCallsItselfIsRefusedInTheProcessThatRunsItWhereverItsCallerRuns() {
        val config = named()
        OptimusCore.builder().config(config).redis(TestRedis.url).hosts(emptyList()).build().use { caller ->
            OptimusCore.builder().config(config).redis(TestRedis.url).hosts("counter").build().use { host ->
                val outer = caller.counter()
                host.counter()
                caller.start()
                host.start()
                assertRefusedFromInsideItselfInAnotherProcess(outer, reentering = 2)
            }
        }
    }

    /**
     * Two processes host the chain unordered: the block's call goes to the other host, which is
     * free, and the recursion of one level succeeds.
     */
    @Test
    fun aChainHostedUnorderedByTwoProcessesMayCallItselfThroughTheOther() {
        val config = named()
        val unordered = { OptimusCore.builder().config(config).redis(TestRedis.url).hosts("counter").hosting("counter", Hosting.UNORDERED).build() }
        unordered().use { first ->
            unordered().use { second ->
                val outer = first.counter()
                second.counter()
                first.start()
                second.start()
                assertEquals(1, outer.process(1), "one process ran the outer call, the other the inner")
            }
        }
    }

    /**
     * Two cores of one topology in one process: the host's block calls the chain through the other
     * core's block, which keeps its own record of the requests its threads run, so the call is not
     * refused. It waits, and the outer call ends by its call timeout; the inner one ends by its
     * own a moment later, and the chain then serves the next call (docs/architecture.md, Errors).
     */
    @Test
    fun aCallThroughAnotherCoreOfTheTopologyIsNotSeenAndEndsByTheCallTimeout() {
        val config = named()
        val timeout = Duration.ofSeconds(2)
        OptimusCore.builder().config(config).redis(TestRedis.url).hosts(emptyList()).callTimeout(timeout).build().use { caller ->
            OptimusCore.builder().config(config).redis(TestRedis.url).hosts("counter").callTimeout(timeout).build().use { host ->
                val viaCaller = AtomicReference<Block<Int, Int>>()
                val outer = caller.chain("counter") { x: Int -> x }.toBlock()
                host.chain("counter") { x: Int -> if (x > 0) viaCaller.get().process(x - 1) + 1 else 0 }.toBlock()
                viaCaller.set(outer)
                caller.start()
                host.start()
                assertEquals(0, outer.process(0), "a call that does not recurse")
                val began = System.nanoTime()
                val failure = assertThrows(dev.prime.PrimeException::class.java) { outer.process(1) }
                val took = Duration.ofNanos(System.nanoTime() - began)
                assertTrue("did not reply within $timeout" in failure.message!!, failure.toString())
                assertTrue(took >= timeout, "ended by the call timeout, after $took")
                // the inner call ends by its own timeout a moment later; the next call waits for that
                assertEquals(0, outer.process(0), "the chain serves the next call")
            }
        }
    }

    /** Declares chain `counter`, whose block calls the block returned here with one less, down to 0. */
    private fun OptimusCore.counter(): Block<Int, Int> {
        val self = AtomicReference<Block<Int, Int>>()
        self.set(chain("counter") { x: Int -> if (x > 0) self.get().process(x - 1) + 1 else 0 }.toBlock())
        return self.get()
    }

    private fun named(): CoreConfig = CoreConfig.builder().name("recursive-call-${System.nanoTime()}").build()
}

package dev.prime.optimus

import dev.prime.Block
import dev.prime.CoreConfig
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import java.util.concurrent.atomic.AtomicReference

/**
 * A chain whose block calls its own chain: each service takes one request at a time, so the
 * call would wait for itself. It is refused at once where it is made, on the thread of the
 * chain's service or of a service its call waits for in the same process (the kit checks it in
 * one process); a service given [Hosting.UNORDERED] is not refused, since another host may take
 * the call.
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
     * core's block. That core keeps its own record of the requests its threads run, but the
     * service that waits for the call is on the call's path in this process ([CallPaths]), so the
     * call is refused at once, not by the call timeout; the chain then serves the next call.
     */
    @Test
    fun aCallThroughAnotherCoreOfTheTopologyIsRefusedAtOnce() {
        val config = named()
        OptimusCore.builder().config(config).redis(TestRedis.url).hosts(emptyList()).build().use { caller ->
            OptimusCore.builder().config(config).redis(TestRedis.url).hosts("counter").build().use { host ->
                val viaCaller = AtomicReference<Block<Int, Int>>()
                val outer = caller.chain("counter") { x: Int -> x }.toBlock()
                host.chain("counter") { x: Int -> if (x > 0) viaCaller.get().process(x - 1) + 1 else 0 }.toBlock()
                viaCaller.set(outer)
                caller.start()
                host.start()
                assertRefusedFromInsideItselfInAnotherProcess(outer, reentering = 1)
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

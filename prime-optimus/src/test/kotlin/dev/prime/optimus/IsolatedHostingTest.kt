package dev.prime.optimus

import dev.prime.Block
import dev.prime.CoreConfig
import dev.prime.topology.TopologyNode
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration
import java.util.concurrent.CountDownLatch
import java.util.concurrent.Executors
import java.util.concurrent.Future
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicInteger

/**
 * `isolate(chain)` promises that the shared chain never runs for two calls at once. A service
 * that runs for an isolated chain hosted [Hosting.UNORDERED] (competing consumers) would break
 * it: every host takes a call at once. Such a mode is refused at `start()`, read from the
 * topology, also in a process that hosts the isolated chain but none of its users, and a user
 * declared after the start is refused at once.
 */
class IsolatedHostingTest {

    /**
     * Two processes host the isolated chain's service unordered, each one of its users: calls
     * through both users would run the shared block at once (both enter it, each waiting for the
     * other, within bounded waits). The hosts' `start()` refuses the mode instead.
     */
    @Test
    fun anIsolatedChainHostedUnorderedByTwoCoresIsRefusedAtStartInsteadOfRunningTwiceAtOnce() {
        val name = "isolated-unordered-${System.nanoTime()}"
        val inside = AtomicInteger()
        val most = AtomicInteger()
        val bothIn = CountDownLatch(2)
        val block = Block<Int, Int> { x ->
            most.accumulateAndGet(inside.incrementAndGet(), ::maxOf)
            try {
                bothIn.countDown()
                bothIn.await(3, TimeUnit.SECONDS) // the second call enters within this, if it can
                x
            } finally {
                inside.decrementAndGet()
            }
        }
        val first = host(name, "counter@1", "counter")
        val second = host(name, "counter@2", "counter")
        val caller = core(name).hosts(emptyList()).build()
        val pool = Executors.newFixedThreadPool(2)
        try {
            first.counter(block)
            second.counter(block)
            val (one, two) = caller.counter(block)
            caller.start()
            val refused = runCatching { first.start(); second.start() }.exceptionOrNull()
            if (refused == null) { // not refused: the promise must hold all the same
                val calls: List<Future<Int>> = listOf(pool.submit<Int> { one.process(1) }, pool.submit<Int> { two.process(2) })
                calls.forEach { it.get(PATIENCE.toSeconds(), TimeUnit.SECONDS) }
                assertEquals(1, most.get(), "the isolated chain's block ran for ${most.get()} calls at once")
            }
            assertTrue(refused is IllegalArgumentException, "start() refuses Hosting.UNORDERED: $refused")
            assertNamesServiceChainAndFix(refused!!.message!!, "counter", "counter")
            assertEquals(0, most.get(), "nothing ran")
        } finally {
            pool.shutdownNow()
            caller.close()
            second.close()
            first.close()
        }
    }

    /**
     * A process that hosts only the isolated chain's service (its users run elsewhere) knows from
     * the topology it declares that the service runs for an isolated chain: here the second chain
     * of a linked chain, hosted unordered, is refused.
     */
    @Test
    fun aProcessThatHostsTheIsolatedChainButNoneOfItsUsersRefusesUnorderedForAnyOfItsServices() {
        val name = "isolated-unordered-host-${System.nanoTime()}"
        core(name).hosts("first", "second").hosting("second", Hosting.UNORDERED).build().use { core ->
            val isolated = core.isolate(core.chain("first") { x: Int -> x + 1 }.then(core.chain("second") { x: Int -> x * 2 }))
            isolated.newUser()
            isolated.newUser()
            val refused = assertThrows(IllegalArgumentException::class.java) { core.start() }
            assertNamesServiceChainAndFix(refused.message!!, "second", "first>second")
        }
    }

    /**
     * A template's part runs only for the isolated chain that consumed the template: the chain a
     * guard runs, hosted unordered, is refused as the isolated chain's own service would be.
     */
    @Test
    fun aTemplatesPartInsideAnIsolatedChainIsRefusedUnorderedToo() {
        val name = "isolated-unordered-part-${System.nanoTime()}"
        core(name).hosting("inner", Hosting.UNORDERED).build().use { core ->
            val guarded = core.guard({ x: Int -> x > 0 }, core.chain("inner") { x: Int -> x * 2 }) { x: Int -> x }
            core.isolate(guarded).newUser()
            val refused = assertThrows(IllegalArgumentException::class.java) { core.start() }
            assertNamesServiceChainAndFix(refused.message!!, "inner", core.topology().nodes().first { it is TopologyNode.Guard }.name())
        }
    }

    /**
     * The isolated chain has no user yet at the start (the topology does not show it isolated),
     * and its service is hosted unordered: its first user, made after the start, is refused at
     * once and leaves no node behind. The users' own services may be unordered (they wait for the
     * isolated chain's one host).
     */
    @Test
    fun aUserMadeAfterTheStartOfAnIsolatedChainHostedUnorderedIsRefusedAtOnce() {
        val name = "isolated-unordered-late-${System.nanoTime()}"
        core(name).hosting("counter", Hosting.UNORDERED).build().use { core ->
            val isolated = core.isolate(core.chain("counter") { x: Int -> x })
            core.start()
            val refused = assertThrows(IllegalArgumentException::class.java) { isolated.newUser() }
            assertNamesServiceChainAndFix(refused.message!!, "counter", "counter")
            assertFalse(core.topology().node("counter@1").isPresent, "the refused user left no node")
        }
        core(name + "-users").hosting("counter@1", Hosting.UNORDERED).build().use { core ->
            val user = core.isolate(core.chain("counter") { x: Int -> x + 1 }).newUser().toBlock()
            core.start()
            assertEquals(2, user.process(1), "an unordered user of an exclusive isolated chain")
        }
    }

    /**
     * `PrimeCore.isolate` on Optimus: calls from users hosted in two processes never overlap in a
     * shared chain of one service (its one host takes one call at a time), although each process
     * keeps the turns of its own users only. The block waits (bounded) for a second call to enter
     * beside it; none does.
     */
    @Test
    fun usersInTwoProcessesNeverOverlapInASharedChainOfOneService() {
        val name = "isolated-two-user-hosts-${System.nanoTime()}"
        val inside = AtomicInteger()
        val most = AtomicInteger()
        val entered = AtomicInteger()
        val second = CountDownLatch(2)
        val block = Block<Int, Int> { x ->
            most.accumulateAndGet(inside.incrementAndGet(), ::maxOf)
            entered.incrementAndGet()
            try {
                second.countDown()
                second.await(1, TimeUnit.SECONDS) // a second call entering beside this one ends the wait
                x
            } finally {
                inside.decrementAndGet()
            }
        }
        val cores = listOf(
            core(name).hosts("counter").build(),
            core(name).hosts("counter@1").build(),
            core(name).hosts("counter@2").build(),
            core(name).hosts(emptyList()).build(),
        )
        val pool = Executors.newFixedThreadPool(2)
        try {
            val users = cores.map { it.counter(block) }
            cores.forEach { it.start() }
            val (one, two) = users.last()
            val calls: List<Future<Int>> = listOf(pool.submit<Int> { one.process(1) }, pool.submit<Int> { two.process(2) })
            assertEquals(listOf(1, 2), calls.map { it.get(PATIENCE.toSeconds(), TimeUnit.SECONDS) })
            assertEquals(2, entered.get(), "both calls ran")
            assertEquals(1, most.get(), "calls in the shared chain at once")
        } finally {
            pool.shutdownNow()
            cores.reversed().forEach { it.close() }
        }
    }

    private fun assertNamesServiceChainAndFix(message: String, service: String, chain: String) {
        assertTrue("'$service'" in message, "names the service: $message")
        assertTrue("isolated chain '$chain'" in message, "names the isolated chain: $message")
        assertTrue("Hosting.UNORDERED" in message && "Hosting.EXCLUSIVE" in message && "Hosting.ORDERED" in message, message)
    }

    /** The isolated counter's two users, declared in [this] core. */
    private fun OptimusCore.counter(block: Block<Int, Int>): Pair<Block<Int, Int>, Block<Int, Int>> {
        val isolated = isolate(chain("counter", block))
        return isolated.newUser().toBlock() to isolated.newUser().toBlock()
    }

    private fun host(name: String, vararg services: String): OptimusCore =
        core(name).hosts(*services).hosting("counter", Hosting.UNORDERED).build()

    private fun core(name: String): OptimusCore.Builder =
        OptimusCore.builder().config(CoreConfig.builder().name(name).build()).redis(TestRedis.url).leaseTime(LEASE)

    private companion object {
        val LEASE: Duration = Duration.ofSeconds(2)
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

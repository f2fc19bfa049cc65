package dev.prime.optimus

import dev.prime.Block
import dev.prime.ChainFailedException
import dev.prime.CoreConfig
import dev.prime.PrimeException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertInstanceOf
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicInteger
import java.util.concurrent.atomic.AtomicReference

/**
 * A block of an isolated chain that calls the same isolated chain through another user
 * ([SelfCalls]): refused at once where the call is made on the thread of the chain's service,
 * wherever the users run; a call made on another service's thread on the chain's behalf waits,
 * as any call for a busy isolated chain, until the call timeout.
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
                assertEquals(0, outer.process(0), "a call that does not re-enter")
                val began = System.nanoTime()
                val failure = assertThrows(ChainFailedException::class.java) { outer.process(1) }
                assertTrue(
                    System.nanoTime() - began < Duration.ofSeconds(10).toNanos(),
                    "refused at once, not by the call timeout of 60 s",
                )
                assertEquals("counter", failure.chainName(), failure.toString())
                val remote = assertInstanceOf(RemoteFailureException::class.java, failure.cause)
                assertTrue("IllegalStateException" in remote.message!!, remote.message)
                assertTrue("called from inside itself" in remote.message!!, remote.message)
                assertEquals(0, outer.process(0), "the isolated chain serves the next call")
            }
        }
    }

    /**
     * The isolated chain's block calls another chain, whose block calls the isolated chain: that
     * call runs on the other chain's service thread, which cannot know it is made on the isolated
     * chain's behalf. It waits, and the outer call ends by its call timeout; the calls that waited
     * end by theirs, give up, and the isolated chain then serves the next call.
     */
    @Test
    fun aCallFromInsideItselfThroughAnotherServiceEndsByTheCallTimeout() {
        val timeout = Duration.ofSeconds(2)
        OptimusCore.builder().config(named()).redis(TestRedis.url).callTimeout(timeout).build().use { core ->
            val user = AtomicReference<Block<Int, Int>>()
            val relay = core.chain("relay") { x: Int -> user.get().process(x) }.toBlock()
            val isolated = core.isolate(core.chain("counter") { x: Int -> if (x > 0) relay.process(x - 1) + 1 else 0 })
            val outer = isolated.newUser().toBlock()
            user.set(isolated.newUser().toBlock())
            core.start()
            val began = System.nanoTime()
            val failure = assertThrows(PrimeException::class.java) { outer.process(1) }
            val took = Duration.ofNanos(System.nanoTime() - began)
            assertTrue("did not reply within $timeout" in failure.message!!, failure.toString())
            assertTrue(took >= timeout, "ended by the call timeout, after $took")
            // the inner calls end by their own timeouts a moment later; the next call waits for that
            assertEquals(0, outer.process(0), "the isolated chain serves the next call")
        }
    }

    /**
     * An unordered isolated chain's service whose seat lapsed starts a new run while the old run's
     * block still runs (it waits at most a lease time for it): the old block, which calls the
     * isolated chain after the new run entered its block, is refused at once as well, although
     * two runs of the service are in their blocks in this process.
     */
    @Test
    fun aCallFromInsideItselfIsRefusedWhileANewRunOfAnUnorderedServiceRunsItsBlock() {
        val name = "self-call-reseat-${System.nanoTime()}"
        val patience = Duration.ofSeconds(20)
        val entries = AtomicInteger()
        val oldEntered = CountDownLatch(1)
        val newEntered = CountDownLatch(1)
        val oldCalled = CountDownLatch(1)
        val oldCallFailure = AtomicReference<Throwable>()
        val inner = AtomicReference<Block<Int, Int>>()
        OptimusCore.builder()
            .config(CoreConfig.builder().name(name).build())
            .redis(TestRedis.url)
            .leaseTime(Duration.ofSeconds(1)) // a heartbeat every third of it sees the lapse soon
            .callTimeout(Duration.ofSeconds(3))
            .hosting("counter", Hosting.UNORDERED)
            .build().use { core ->
                val isolated = core.isolate(
                    core.chain("counter") { x: Int ->
                        if (entries.incrementAndGet() == 1) {
                            oldEntered.countDown()
                            // the old run: its job is cancelled when the seat lapses; it waits on regardless
                            awaitIgnoringInterrupts(newEntered, patience)
                            try {
                                inner.get().process(0)
                            } catch (e: Exception) {
                                oldCallFailure.set(e)
                            } finally {
                                oldCalled.countDown()
                            }
                        } else {
                            newEntered.countDown()
                            awaitIgnoringInterrupts(oldCalled, patience)
                        }
                        x
                    },
                )
                val outer = isolated.newUser().toBlock()
                inner.set(isolated.newUser().toBlock())
                core.start()
                val call = Thread { runCatching { outer.process(1) } }
                call.start()
                try {
                    assertTrue(oldEntered.await(patience.toMillis(), TimeUnit.MILLISECONDS), "the first run entered the block")
                    Jedis(URI(TestRedis.url)).use { jedis ->
                        val keys = Keys(name)
                        val instance = jedis.smembers(keys.serviceHosts("counter")).single().toString(UTF_8)
                        jedis.del(keys.hostSeatLease("counter", instance)) // the seat lapses: a new run starts
                    }
                    assertTrue(newEntered.await(patience.toMillis(), TimeUnit.MILLISECONDS), "a new run entered the block")
                    assertTrue(oldCalled.await(patience.toMillis(), TimeUnit.MILLISECONDS), "the old run's call ended")
                    val failure = oldCallFailure.get()
                    assertInstanceOf(IllegalStateException::class.java, failure, "refused at once: $failure")
                    assertTrue("called from inside itself" in failure.message!!, failure.message)
                } finally {
                    call.join(patience.toMillis())
                }
            }
    }

    /** Waits for [latch] up to [patience], through interrupts (kept for after the wait). */
    private fun awaitIgnoringInterrupts(latch: CountDownLatch, patience: Duration) {
        val deadline = System.nanoTime() + patience.toNanos()
        var interrupted = false
        while (latch.count > 0 && System.nanoTime() < deadline) {
            try {
                latch.await(deadline - System.nanoTime(), TimeUnit.NANOSECONDS)
            } catch (_: InterruptedException) {
                interrupted = true
            }
        }
        if (interrupted) Thread.currentThread().interrupt()
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

package dev.prime.optimus

import dev.prime.Block
import dev.prime.Chain
import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.GenericService
import dev.prime.PrimeCore
import dev.prime.Source
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertSame
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.function.Executable
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * A `start()` that throws leaves the core failed to start: a second `start()`, every declaration,
 * and (as before a start) a publish or a call are refused with an [IllegalStateException] that
 * says start() failed, quotes its failure (the cause) and says to close the core and make a new
 * one; `close()` releases every thread, connection, lease and record in Redis the partial start
 * took. Liberty and Radiant have no failing start, so this is Optimus's, with real causes: a host
 * the topology lacks, and a service another live process hosts.
 */
class FailedStartTest {

    @Test
    fun aCoreToldToHostAnUnknownServiceIsFailedToStartAndClosesClean() {
        val topology = "failed-start-unknown-${System.nanoTime()}"
        val core = OptimusCore.builder().config(CoreConfig.builder().name(topology).build())
            .redis(TestRedis.url).hosts("double", "nowhere").build()
        val double = core.chain("double", Block<Int, Int> { it * 2 })
        val unused = core.chain("unused", Block<Int, Int> { it + 1 })
        val events = EventBlock<Int>()
        val source = core.source("ticks", events)
        val calls = double.toBlock()
        val failure = assertThrows(IllegalArgumentException::class.java) { core.start() }
        assertTrue("nowhere" in failure.message!!, failure.message)

        assertRefusedAfter(failure, core, unused, source, events)
        assertRefused(failure, "calling chain 'double'") { calls.process(1) }

        core.close()
        assertNoThreadsLeft(core, topology, emptySet())
        assertNoConnectionsLeft(topology)
    }

    @Test
    fun aCoreRefusedAServiceAnotherProcessHostsIsFailedToStartAndReleasesWhatItTook() {
        val topology = "failed-start-lease-${System.nanoTime()}"
        val lease = Duration.ofMillis(600)
        fun builder(vararg hosts: String) = OptimusCore.builder().config(CoreConfig.builder().name(topology).build())
            .redis(TestRedis.url).leaseTime(lease).hosts(*hosts)
        builder("poller").build().use { holder ->
            holder.service("poller", GenericService { Thread.sleep(10) })
            holder.start()
            val before = keys(topology)
            val threadsBefore = liveThreads(topology)
            val core = builder("poller", "double", "ordered").hosting("ordered", Hosting.ORDERED).build()
            val double = core.chain("double", Block<Int, Int> { it * 2 })
            core.chain("ordered", Block<Int, Int> { it + 1 }).toBlock()
            val unused = core.chain("unused", Block<Int, Int> { it + 1 })
            val events = EventBlock<Int>()
            val source = core.source("ticks", events)
            core.service("poller", GenericService { Thread.sleep(10) })
            val calls = double.toBlock()
            val failure = assertThrows(IllegalStateException::class.java) { core.start() }
            assertTrue("already hosted by" in failure.message!!, failure.message)
            assertTrue(liveThreads(topology).size > threadsBefore.size, "the failed start left its heartbeat running")
            assertTrue(keys(topology).size > before.size, "the failed start wrote to Redis: ${keys(topology) - before}")

            assertRefusedAfter(failure, core, unused, source, events)
            assertRefused(failure, "calling chain 'double'") { calls.process(1) }

            core.close()
            // gone, but for the records of hosting modes, which every host writes and which lapse (as documented) a
            // lease time after the last host stopped
            val left = keys(topology) - before
            assertTrue(left.all { it.endsWith(":hosting") }, "what the failed start wrote to Redis is gone, left: $left")
            Jedis(URI(TestRedis.url)).use { jedis ->
                for (key in left) assertTrue(jedis.pttl(key) in 1..lease.toMillis(), "$key lapses within the lease time")
            }
            assertNoThreadsLeft(core, topology, threadsBefore)
        }
        // the holder has the same name: its connections are told from the failed core's once it closed too
        assertNoConnectionsLeft(topology)
    }

    /** A second start(), each kind of declaration and a publish, refused as a failed start's. */
    private fun assertRefusedAfter(
        failure: Throwable,
        core: OptimusCore,
        unused: Chain<Int, Int>,
        source: Source<Int>,
        events: EventBlock<Int>,
    ) {
        assertRefused(failure, "a second start()", core::start)
        assertRefused(failure, "a declaration") { core.chain("late", Block<Int, Int> { it }) }
        assertRefused(failure, "a declaration") { core.source("late-source", EventBlock<Int>()) }
        assertRefused(failure, "a declaration") { unused.toBlock() }
        assertRefused(failure, "a declaration") { core.link(source, unused) }
        assertRefused(failure, "a declaration") { core.timer("late-timer", Duration.ofSeconds(1)) }
        assertRefused(failure, "a declaration") { core.merge(source, source) }
        assertRefused(failure, "a declaration") { core.service("late-service", GenericService { Thread.sleep(10) }) }
        assertRefused(failure, "publishing to an Optimus source") { events.publish(1) }
        assertTrue(core.topology().node("late").isEmpty, "a refused declaration leaves nothing")
        assertTrue(core.isStarted && !core.isClosed)
    }

    private fun assertRefused(failure: Throwable, what: String, action: Executable) {
        val refused = assertThrows(IllegalStateException::class.java, action)
        assertSame(failure, refused.cause, "the refusal carries the start's failure: $refused")
        val message = refused.message!!
        assertTrue(what in message, "says what is refused ($what): $message")
        assertTrue("failed to start" in message && failure.message!! in message, "quotes the failure: $message")
        assertTrue("close() it" in message && "make a new core" in message, "says what to do: $message")
    }

    private fun assertNoThreadsLeft(core: PrimeCore, topology: String, threadsBefore: Set<Thread>) {
        assertTrue(core.isClosed)
        val deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(10)
        val left = liveThreads(topology) - threadsBefore
        for (thread in left) thread.join(((deadline - System.nanoTime()) / 1_000_000).coerceAtLeast(1))
        assertEquals(emptyList<String>(), (liveThreads(topology) - threadsBefore).map { it.name }, "threads left")
    }

    private fun assertNoConnectionsLeft(topology: String) {
        val deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(10)
        val never = CountDownLatch(1)
        // Redis drops a closed connection when it reads its end: a bounded wait for that
        while (clientsOf(topology).isNotEmpty() && System.nanoTime() < deadline) {
            never.await(10, TimeUnit.MILLISECONDS) // a bounded pause between looks
        }
        assertEquals(emptyList<String>(), clientsOf(topology), "connections left")
    }

    private fun liveThreads(topology: String): Set<Thread> =
        Thread.getAllStackTraces().keys.filterTo(HashSet()) { it.isAlive && it.name.startsWith("prime-$topology-") }

    private fun keys(topology: String): Set<String> = Jedis(URI(TestRedis.url)).use { TestRedis.keysOf(it, topology).toSet() }

    /** The names of the Redis connections of [topology]'s cores, sorted. */
    private fun clientsOf(topology: String): List<String> = Jedis(URI(TestRedis.url)).use { jedis ->
        jedis.clientList().lines().mapNotNull { line -> line.split(' ').firstOrNull { it.startsWith("name=prime-$topology") } }
            .filter { it == "name=prime-$topology" || it.startsWith("name=prime-$topology-") }.sorted()
    }
}

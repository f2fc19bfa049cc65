package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.PrimeException
import dev.prime.Reader
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.UUID

/**
 * [OptimusCore.deleteKeys] on every Optimus set-up: it deletes all of a closed core's topology
 * and nothing of another's, and refuses a core that is not closed.
 */
abstract class DeleteKeysTest {
    /** The Redis URL the cores of this variant use. */
    protected abstract val url: String

    /** The keys of [topology], read straight from the server that holds them. */
    protected abstract fun keysOf(topology: String): List<String>

    @Test
    fun deletesEveryKeyOfAClosedCoresTopologyAndNoneOfAnothers() {
        val name = uniqueName("retired")
        val otherName = uniqueName("kept")
        core(otherName).use { other ->
            val readings = EventBlock<Int>()
            val kept = readsOneValue(other, readings)
            val otherKeys = keysOf(otherName)
            assertTrue(otherKeys.isNotEmpty(), "the other topology has keys")

            val core = core(name)
            core.use {
                val events = EventBlock<Int>()
                val out = core.source("numbers", events)
                    .then(core.chain("fragile") { x: Int -> check(x != 2) { "two is refused" }; x * 10 })
                    .reader()
                core.start()
                events.publish(1)
                events.publish(2) // dead-lettered
                events.publish(3)
                assertEquals(10, out.take(PATIENCE).orElseThrow())
                assertEquals(30, out.take(PATIENCE).orElseThrow())
                assertEquals(1, core.deadLetters("fragile").size)
            }
            val before = keysOf(name)
            assertTrue(before.any { ":svc:fragile:dead" in it }, "a dead letter, a source log and more are left after close: $before")

            assertEquals(before.size.toLong(), core.deleteKeys(), "deleted: every key that was there ($before)")
            assertEquals(emptyList<String>(), keysOf(name), "nothing of the topology is left")
            assertEquals(otherKeys.sorted(), keysOf(otherName).sorted(), "the other topology keeps every key")
            assertEquals(0L, core.deleteKeys(), "run again, there is nothing to delete")

            readings.publish(8) // the other core goes on
            assertEquals(8, kept.take(PATIENCE).orElseThrow())
        }
    }

    @Test
    fun refusesACoreThatIsNotClosedAndDeletesNothing() {
        val name = uniqueName("open")
        core(name).use { core ->
            val events = EventBlock<Int>()
            val out = core.source("numbers", events).reader()
            val beforeStart = assertThrows(IllegalStateException::class.java) { core.deleteKeys() }
            assertEquals(
                "core '$name' is not closed: close() it before deleteKeys() (its services and readers use those keys)",
                beforeStart.message,
            )
            core.start()
            events.publish(7)
            assertEquals(7, out.take(PATIENCE).orElseThrow())
            val keys = keysOf(name)
            assertThrows(IllegalStateException::class.java) { core.deleteKeys() }
            assertEquals(keys.sorted(), keysOf(name).sorted(), "a refused deleteKeys() deletes nothing")
        }
    }

    @Test
    fun aToolRetiresATopologyWithACoreOfItsNameBuiltAndClosedWithoutStarting() {
        val name = uniqueName("tool")
        core(name).use { readsOneValue(it) }
        val left = keysOf(name)
        assertTrue(left.isNotEmpty(), "the topology's keys outlive its core")

        val tool = core(name)
        tool.close()
        assertEquals(left.size.toLong(), tool.deleteKeys())
        assertEquals(emptyList<String>(), keysOf(name))
    }

    @Test
    fun refusesWhileAnotherProcessRunsTheTopologyAndDeletesOnceItIsClosed() {
        val name = uniqueName("shared")
        val core = core(name)
        core.use { readsOneValue(it) }
        // another process of the topology: it hosts nothing and reads the source
        OptimusCore.builder().config(CoreConfig.builder().name(name).build()).redis(url).hosts(emptyList()).build().use { other ->
            other.source("numbers", EventBlock<Int>()).reader()
            other.start()
            val keys = keysOf(name)
            val refused = assertThrows(IllegalStateException::class.java) { core.deleteKeys() }
            assertTrue(
                refused.message!!.startsWith("topology '$name' is still run by 1 other process(es) on this Redis ("),
                refused.message,
            )
            assertTrue("nothing was deleted" in refused.message!!, refused.message)
            assertTrue(keysOf(name).containsAll(keys), "a refused deleteKeys() deletes nothing")
        }
        assertTrue(core.deleteKeys() > 0, "once the other process closed")
        assertEquals(emptyList<String>(), keysOf(name))
    }

    private fun core(name: String): OptimusCore =
        OptimusCore.builder().config(CoreConfig.builder().name(name).build()).redis(url).build()

    /**
     * Declares a source with a reader on [core], starts it and sees one value through: the
     * topology has keys in Redis. Returns the reader, to read [events]' later values.
     */
    protected fun readsOneValue(core: OptimusCore, events: EventBlock<Int> = EventBlock()): Reader<Int> {
        val out = core.source("numbers", events).reader()
        core.start()
        events.publish(7)
        assertEquals(7, out.take(PATIENCE).orElseThrow())
        return out
    }

    protected companion object {
        val PATIENCE: Duration = Duration.ofSeconds(20)

        fun uniqueName(what: String) = "delete-keys-$what-" + UUID.randomUUID().toString().substring(0, 8)
    }
}

/** On one `redis-server`; also the cases that do not depend on the set-up. */
class DeleteKeysOnRedisTest : DeleteKeysTest() {
    override val url: String get() = TestRedis.url

    override fun keysOf(topology: String): List<String> = Jedis(URI(TestRedis.url)).use { TestRedis.keysOf(it, topology) }

    @Test
    fun aCoreOnAnEmbeddedRedisOfItsOwnHasNothingToDelete() {
        val core = OptimusCore()
        core.use { readsOneValue(it) }
        assertEquals(0L, core.deleteKeys())
    }

    @Test
    fun givesUpWithRedisUnavailableWhenRedisCannotBeReached() {
        FaultProxy(TestRedis.url).use { proxy ->
            val name = uniqueName("unreachable")
            val core = OptimusCore.builder().config(CoreConfig.builder().name(name).build()).redis(proxy.url).build()
            core.use { it.start() }
            proxy.freeze()
            val started = System.nanoTime()
            val failure = assertThrows(RedisUnavailableException::class.java) { core.deleteKeys() }
            val seconds = (System.nanoTime() - started) / 1e9
            assertTrue(seconds < 15, "gave up after $seconds s, within its 10 s and a connect timeout")
            assertTrue("delete the keys of topology '$name'" in failure.message!!, failure.message)
        }
    }

    @Test
    fun anInterruptWhileRedisIsDownEndsItAtOnceWithThePrimeExceptionOfAnyOptimusWaitAndKeepsTheFlag() {
        FaultProxy(TestRedis.url).use { proxy ->
            val core = OptimusCore.builder().config(CoreConfig.builder().name(uniqueName("interrupted")).build()).redis(proxy.url).build()
            core.use { it.start() }
            proxy.refuse() // every attempt fails at once: the deletion waits between attempts
            Thread.currentThread().interrupt()
            val started = System.nanoTime()
            try {
                assertThrows(PrimeException::class.java) { core.deleteKeys() }
                assertTrue(Thread.currentThread().isInterrupted, "the interrupt flag is kept")
            } finally {
                Thread.interrupted()
            }
            val seconds = (System.nanoTime() - started) / 1e9
            assertTrue(seconds < 2, "ended at once, not after its 10 s: $seconds s")
        }
    }
}

/** Through a proxy that holds every reply of Redis for half a millisecond. */
class DeleteKeysOnSlowRedisTest : DeleteKeysTest() {
    override val url: String get() = FaultProxy.slowLinkTo(TestRedis.url)

    override fun keysOf(topology: String): List<String> = Jedis(URI(TestRedis.url)).use { TestRedis.keysOf(it, topology) }
}

/** On a Redis Cluster: the topology's keys are on the master of its slot. */
class DeleteKeysOnClusterTest : DeleteKeysTest() {
    override val url: String get() = TestCluster.url

    override fun keysOf(topology: String): List<String> =
        TestCluster.cluster.masterOfKey("prime:{$topology}:").jedis().use { TestRedis.keysOf(it, topology) }

    @Test
    fun withReplicaAcksTheDeletionIsConfirmedByAReplicaAsEveryOperationIs() {
        val name = uniqueName("acked")
        val core = OptimusCore.builder().config(CoreConfig.builder().name(name).build()).redis(url).replicaAcks(1).build()
        core.use {
            val twice = core.chain("twice") { x: Int -> 2 * x }.toBlock()
            core.start()
            assertEquals(42, twice.process(21))
        }
        val master = TestCluster.cluster.masterOfKey("prime:{$name}:")
        val waitsBefore = master.jedis().use { waits(it.info("commandstats")) }
        assertTrue(core.deleteKeys() > 0)
        val waitsAfter = master.jedis().use { waits(it.info("commandstats")) }
        assertTrue(waitsAfter > waitsBefore, "the deletion waited for a replica (WAIT calls: $waitsBefore, then $waitsAfter)")
        val replica = TestCluster.cluster.replicaOf(master)
        assertEquals(emptyList<String>(), replica.jedis().use { TestRedis.keysOf(it, name) }, "the replica has none of them")
    }

    /** How many `WAIT` commands the server ran, from its `INFO commandstats`. */
    private fun waits(commandStats: String): Long =
        commandStats.lines().firstOrNull { it.startsWith("cmdstat_wait:") }
            ?.substringAfter("calls=")?.substringBefore(',')?.toLong() ?: 0L
}

package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import redis.clients.jedis.params.ScanParams
import java.net.URI
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration

/**
 * Readers of a process that died (a worker JVM killed with SIGKILL) are reclaimed by a live
 * process of the topology once the dead one's lease expired: they leave the source's reader set,
 * their lists are deleted, and publishing writes to the live readers only again.
 */
class ReclaimTest {

    @Test
    fun readersOfAKilledProcessAreReclaimedWithinTheLeaseAndAHeartbeat() {
        val name = "reclaim"
        val lease = Duration.ofSeconds(1)
        val keys = Keys(name)
        EmbeddedRedis.start().use { redis ->
            Jedis(URI(redis.uri)).use { jedis ->
                val events = EventBlock<Int>()
                OptimusCore.builder().config(CoreConfig.builder().name(name).build()).redis(redis.uri).leaseTime(lease).build().use { core ->
                    val own = core.source("numbers", events).reader()
                    core.start()
                    val readerSet = keys.sourceReaders("numbers")
                    var withDead: Long

                    WorkerProcess.start(LeaseWorkerMain::class.java, redis.uri, name, lease.toMillis().toString(), "readers", "$READERS").use { worker ->
                        worker.awaitLine("READY")
                        assertEquals(READERS + 1L, jedis.scard(readerSet), "the worker's readers and this one")
                        (0 until 10).forEach(events::publish) // warms the publishing path up
                        withDead = microsPerPublish(events, 10 until 110)
                        assertEquals((0 until 110).toList(), (0 until 110).map { own.take(PATIENCE).orElseThrow() })
                        val ownList = readerOf(jedis, readerSet, own)
                        val workerLists = readerLists(jedis, name).filter { it != ownList }
                        assertEquals(READERS, workerLists.size, worker.output())
                        assertEquals(110L, jedis.llen(workerLists.first()), "each of the worker's readers got every value")

                        val killed = System.nanoTime()
                        worker.kill()
                        val deadline = killed + (lease + lease.dividedBy(3) + SLACK).toNanos()
                        while (jedis.scard(readerSet) > 1 && System.nanoTime() < deadline) {
                            Thread.onSpinWait()
                            jedis.ping() // paces the loop on Redis round trips
                        }
                        val took = Duration.ofNanos(System.nanoTime() - killed)
                        println("ReclaimTest: $READERS readers of a killed process reclaimed ${took.toMillis()} ms after the kill")
                        assertEquals(1L, jedis.scard(readerSet), "reader set ${took.toMillis()} ms after the kill")
                        assertEquals(setOf(ownList), jedis.smembers(readerSet.toString(UTF_8)), "the live reader stays")
                        assertEquals(listOf<String>(), workerLists.filter { jedis.exists(it) }, "the dead readers' lists are deleted")
                        assertEquals(listOf<String>(), scan(jedis, "prime:{$name}:rdr:*").filter { !it.startsWith(ownList) }, "and their processing lists and counters")
                    }
                    assertEquals(setOf(instanceOf(jedis, keys)), jedis.smembers(keys.instances.toString(UTF_8)), "the dead instance is forgotten")
                    assertEquals(0, scan(jedis, "prime:{$name}:inst:*").count { !it.contains(instanceOf(jedis, keys)) }, "its records are gone")

                    val reclaimed = microsPerPublish(events, 110 until 210)
                    println("ReclaimTest: a publish took $withDead µs with $READERS readers of a live process, $reclaimed µs once reclaimed")
                    assertEquals((110 until 210).toList(), (110 until 210).map { own.take(PATIENCE).orElseThrow() }, "the live reader goes on")
                }
                assertFalse(jedis.exists(keys.instances), "a closed core leaves no instance behind")
                assertTrue(scan(jedis, "prime:{$name}:inst:*").isEmpty(), "nor lease or records")
            }
        }
    }

    @Test
    fun aClosedReaderLeavesItsProcessRecordsSoNothingIsLeftToReclaim() {
        val name = "reclaim-closed-reader"
        val keys = Keys(name)
        Jedis(URI(TestRedis.url)).use { jedis ->
            OptimusCore.builder().config(CoreConfig.builder().name(name).build()).redis(TestRedis.url).build().use { core ->
                val numbers = core.source("numbers", EventBlock<Int>())
                val kept = numbers.reader()
                val closed = numbers.reader()
                core.start()
                val records = keys.instanceLists(instanceOf(jedis, keys))
                assertEquals(2L, jedis.hlen(records), "both readers are recorded as this process's")
                closed.close()
                assertEquals(listOf((kept as OptimusReader<*>).list.toString(UTF_8)), jedis.hkeys(records.toString(UTF_8)).toList())
            }
        }
    }

    @Test
    fun aLeaseTooShortToSurviveAGcPauseIsRefusedWithTheMinimum() {
        val e = assertThrows(IllegalArgumentException::class.java) { OptimusCore.builder().leaseTime(Duration.ofMillis(100)) }
        assertTrue(e.message!!.contains("at least 300 ms") && e.message!!.contains("PT0.1S"), e.message)
    }

    /** Publishes [values]; the mean time per publish in microseconds (a figure printed, not asserted). */
    private fun microsPerPublish(events: EventBlock<Int>, values: IntRange): Long {
        val started = System.nanoTime()
        values.forEach(events::publish)
        return (System.nanoTime() - started) / 1000 / values.count()
    }

    private fun readerLists(jedis: Jedis, name: String): List<String> =
        scan(jedis, "prime:{$name}:rdr:*").filter { !it.endsWith(":proc") && !it.endsWith(":missed") }

    private fun readerOf(jedis: Jedis, readerSet: ByteArray, own: dev.prime.Reader<Int>): String =
        (own as OptimusReader<*>).list.toString(UTF_8).also { assertTrue(jedis.sismember(readerSet, it.toByteArray(UTF_8))) }

    private fun instanceOf(jedis: Jedis, keys: Keys): String =
        jedis.smembers(keys.instances.toString(UTF_8)).single { jedis.exists(keys.instanceLease(it)) }

    private fun scan(jedis: Jedis, pattern: String): List<String> {
        val found = ArrayList<String>()
        var cursor = ScanParams.SCAN_POINTER_START
        var rounds = 0
        do {
            val page = jedis.scan(cursor, ScanParams().match(pattern).count(1000))
            found += page.result
            cursor = page.cursor
            check(++rounds < 10_000) { "SCAN did not finish" }
        } while (cursor != ScanParams.SCAN_POINTER_START)
        return found
    }

    private companion object {
        const val READERS = 500
        val PATIENCE: Duration = Duration.ofSeconds(20)

        /** Scheduling slack on a loaded machine over the lease time and one heartbeat. */
        val SLACK: Duration = Duration.ofSeconds(2)
    }
}

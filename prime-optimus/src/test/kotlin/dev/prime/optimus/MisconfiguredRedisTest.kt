package dev.prime.optimus

import dev.prime.CoreClosedException
import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.PrimeException
import dev.prime.conformance.CapturedStderr
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.params.ParameterizedTest
import org.junit.jupiter.params.provider.CsvSource
import org.junit.jupiter.params.provider.ValueSource
import redis.clients.jedis.Jedis
import redis.clients.jedis.Protocol
import redis.clients.jedis.exceptions.JedisDataException
import java.net.URI
import java.time.Duration
import java.util.concurrent.CompletableFuture
import java.util.concurrent.CountDownLatch
import java.util.concurrent.ExecutionException
import java.util.concurrent.TimeUnit
import java.util.concurrent.TimeoutException

/**
 * A `redis://` URL that names a Redis set up in a way Optimus cannot work with: a read-only
 * replica, a Redis without `LMOVE`/`BLMOVE` (older than 6.2, or with the commands renamed away),
 * a Redis at its `maxclients`. Each runs on a `redis-server` of its own, with the arguments that
 * make it so, stopped at the end.
 */
class MisconfiguredRedisTest {

    /**
     * On a replica's URL, `start()` waits (its writes are refused with `READONLY`, as during a
     * failover) and one WARN says that the Redis is a read-only replica and the URL should name
     * the master; `close()` ends the wait. A publish to a master demoted meanwhile gives up at its
     * timeout with a message that says "read-only replica", not "unreachable".
     */
    @Test
    fun aReplicasUrlSaysOnceThatItIsAReadOnlyReplica() {
        EmbeddedRedis.start().use { master ->
            EmbeddedRedis.builder().arguments("--replicaof", "127.0.0.1", master.port.toString()).start().use { replica ->
                CapturedStderr().use { err ->
                    val core = core("misconf-replica", replica.uri)
                    val start = CompletableFuture.runAsync { core.start() }
                    val warnings = { err.lines().filter { " WARN " in it && "read-only replica" in it && "misconf-replica" in it } }
                    val deadline = System.nanoTime() + Duration.ofSeconds(5).toNanos()
                    while (warnings().isEmpty() && System.nanoTime() < deadline) {
                        try {
                            start.get(50, TimeUnit.MILLISECONDS)
                        } catch (_: TimeoutException) {
                            // start() still waits, as it should
                        }
                    }
                    assertTrue(!start.isDone, "start() on a replica should wait as during a failover, it ended: $start")
                    core.close()
                    val ended = assertThrows(ExecutionException::class.java) { start.get(5, TimeUnit.SECONDS) }
                    assertTrue(ended.cause is CoreClosedException, "start() ended with ${ended.cause}")
                    val lines = warnings()
                    assertEquals(1, lines.size, "read-only replica WARN lines: $lines")
                    assertTrue("give the URL of the master" in lines.single() && replica.uri in lines.single(), lines.single())
                }
            }
            EmbeddedRedis.start().use { demoted ->
                core("misconf-demoted", demoted.uri, Duration.ofSeconds(1)).use { core ->
                    val events = EventBlock<Int>()
                    core.source("numbers", events)
                    core.start()
                    Jedis(URI(demoted.uri)).use { it.replicaof("127.0.0.1", master.port) }
                    val e = assertThrows(RedisUnavailableException::class.java) { events.publish(1) }
                    assertTrue("is a read-only replica" in e.message!! && "URL of the master" in e.message!!, e.message)
                    Jedis(URI(demoted.uri)).use { it.replicaofNoOne() }
                }
            }
        }
    }

    /**
     * A Redis that does not know `LMOVE` or `BLMOVE` (older than 6.2, or with them renamed away)
     * fails `start()` at once with a message naming the command and "Redis 6.2 or newer", instead
     * of services retrying "unknown command" forever.
     */
    @ParameterizedTest
    @CsvSource("LMOVE,false", "BLMOVE,false", "BLMOVE,true")
    fun aRedisWithoutACommandOptimusNeedsFailsTheStartNamingIt(command: String, slow: Boolean) {
        EmbeddedRedis.builder().arguments("--rename-command", command, "").start().use { redis ->
            val url = if (slow) FaultProxy.slowLinkTo(redis.uri) else redis.uri
            core("misconf-no-${command.lowercase()}", url).use { core ->
                core.chain("twice") { x: Int -> 2 * x }.toBlock()
                val e = startFailsAtOnce(core, PrimeException::class.java)
                assertTrue("the command $command" in e.message!! && "Redis 6.2 or newer" in e.message!!, e.message)
            }
        }
    }

    /**
     * A Redis at its `maxclients` refuses a new connection: building a core then fails at once, and
     * a core that needs one more connection fails `start()` at once, each saying "max number of
     * clients reached" and to raise `maxclients`.
     */
    @Test
    fun aRedisAtItsMaxclientsSaysSoAtOnce() {
        EmbeddedRedis.builder().arguments("--maxclients", "1").start().use { redis ->
            Jedis(URI(redis.uri)).use { holder ->
                holder.ping() // the one client Redis allows
                val e = assertThrows(PrimeException::class.java) { core("misconf-full", redis.uri).close() }
                assertTrue("max number of clients reached" in e.message!! && "CONFIG SET maxclients" in e.message!!, e.message)
            }
            core("misconf-maxclients", redis.uri).use { core ->
                core.chain("twice") { x: Int -> 2 * x }.toBlock()
                val e = startFailsAtOnce(core, JedisDataException::class.java)
                assertTrue("max number of clients reached" in e.message!! && "CONFIG SET maxclients" in e.message!!, e.message)
            }
        }
    }

    /**
     * A running core whose connections are cut while Redis is at its `maxclients` (a
     * `CONFIG SET maxclients` below the clients connected, then `CLIENT KILL` of the core's
     * connections): its service and its heartbeat each say once that Redis refuses connections at
     * its `maxclients`, after the lost connection's WARN; a
     * publish meanwhile fails at once saying so; once Redis has room again the service and the
     * publisher reconnect by themselves, and the values published then all arrive, in order, once.
     * On a plain Redis and through the kit's slow link.
     */
    @ParameterizedTest
    @ValueSource(booleans = [false, true])
    fun aRunningCoreCutOffAtMaxclientsSaysSoAndRecoversOnceThereIsRoom(slow: Boolean) {
        EmbeddedRedis.start().use { redis ->
            CapturedStderr().use { err ->
                val url = if (slow) FaultProxy.slowLinkTo(redis.uri) else redis.uri
                core("misconf-cutoff", url, Duration.ofSeconds(1)).use { core ->
                    val events = EventBlock<Int>()
                    val doubled = core.source("numbers", events).then(core.chain("twice") { x: Int -> 2 * x }).reader()
                    core.start()
                    (1..5).forEach { events.publish(it) }
                    assertEquals((1..5).map { 2 * it }, (1..5).map { doubled.take(Duration.ofSeconds(10)).orElseThrow() })
                    Jedis(URI(redis.uri)).use { admin ->
                        admin.configSet("maxclients", "1") // the clients connected stay; no new one is let in
                        val ids = admin.clientList().lines().filter { " name=prime-misconf-cutoff " in " $it " }
                            .map { line -> line.split(' ').first { it.startsWith("id=") }.removePrefix("id=") }
                        assertTrue(ids.isNotEmpty(), admin.clientList())
                        ids.forEach { admin.sendCommand(Protocol.Command.CLIENT, "KILL", "ID", it) }
                        val refused = assertThrows(JedisDataException::class.java) { events.publish(6) }
                        assertTrue("maxclients" in refused.message!!, refused.message)
                        val serviceLines = {
                            err.lines().filter { " WARN " in it && "service 'twice'" in it && "max number of clients reached" in it }
                        }
                        val heartbeatLines = {
                            err.lines().filter { " WARN " in it && "heartbeat" in it && "max number of clients reached" in it }
                        }
                        val pause = CountDownLatch(1)
                        val deadline = System.nanoTime() + Duration.ofSeconds(10).toNanos()
                        while ((serviceLines().isEmpty() || heartbeatLines().isEmpty()) && System.nanoTime() < deadline) {
                            pause.await(20, TimeUnit.MILLISECONDS) // a bounded poll of the log, which only the service writes
                        }
                        val warned = serviceLines()
                        assertEquals(1, warned.size, "the service's WARN lines: $warned")
                        assertTrue("cannot connect to Redis" in warned.single() && "CONFIG SET maxclients" in warned.single(), warned.single())
                        assertEquals(1, heartbeatLines().size, "the heartbeat's WARN lines: ${heartbeatLines()}")
                        admin.configSet("maxclients", "10000")
                    }
                    val roomMade = System.nanoTime()
                    val published = (7..11).toList()
                    published.forEach { events.publish(it) }
                    val arrived = (1..published.size).map { doubled.take(Duration.ofSeconds(10)).orElseThrow() }
                    val recovered = Duration.ofNanos(System.nanoTime() - roomMade)
                    assertEquals(published.map { 2 * it }, arrived, "lost, duplicated or reordered after the cut-off")
                    assertTrue(doubled.take(Duration.ofMillis(300)).isEmpty, "a value arrived twice")
                    assertTrue(recovered < Duration.ofSeconds(5), "recovered after $recovered")
                }
            }
        }
    }

    /**
     * A planned switchover under a running core: its master, in sync with a replica, pauses
     * writes, the replica is promoted and the master made its replica (`REPLICAOF host port`), so
     * it keeps its data and answers writes with `READONLY`. The core waits that out as an outage:
     * a publish meanwhile waits, the core logs the read-only replica WARN once, and once the
     * URL's Redis takes writes again (`REPLICAOF NO ONE`) the publish returns and every value
     * published before, during and after comes out once, in order, with no Redis reset. On a plain
     * Redis and through the kit's slow link.
     */
    @ParameterizedTest
    @ValueSource(booleans = [false, true])
    fun aMasterDemotedUnderARunningCoreIsWaitedOutAndLosesNothing(slow: Boolean) {
        // the replica's first sync at once, not after the default 5 s of a diskless sync
        EmbeddedRedis.builder().arguments("--repl-diskless-sync-delay", "0").start().use { redis ->
            EmbeddedRedis.builder().arguments("--replicaof", "127.0.0.1", redis.port.toString()).start().use { replica ->
                Jedis(URI(redis.uri)).use { master -> Jedis(URI(replica.uri)).use { awaitInSync(master, it) } }
                CapturedStderr().use { err ->
                    val url = if (slow) FaultProxy.slowLinkTo(redis.uri) else redis.uri
                    core("misconf-demoted-running", url, Duration.ofSeconds(20)).use { core ->
                        val events = EventBlock<Int>()
                        val doubled = core.source("numbers", events).then(core.chain("twice") { x: Int -> 2 * x }).reader()
                        core.start()
                        val before = (1..5).toList()
                        before.forEach { events.publish(it) }
                        assertEquals(before.map { 2 * it }, before.map { doubled.take(Duration.ofSeconds(10)).orElseThrow() })
                        val warnings = {
                            err.lines().filter { " WARN " in it && "read-only replica" in it && "misconf-demoted-running" in it }
                        }
                        val during = listOf(6, 7)
                        var paused = 0L
                        var warned = 0L
                        val publishing = Jedis(URI(redis.uri)).use { master ->
                            Jedis(URI(replica.uri)).use { promoted ->
                                // a switchover: writes paused until the replica has them all, the replica promoted, the master demoted
                                paused = System.nanoTime()
                                master.sendCommand(Protocol.Command.CLIENT, "PAUSE", "10000", "WRITE")
                                awaitInSync(master, promoted)
                                promoted.replicaofNoOne()
                                master.replicaof("127.0.0.1", replica.port)
                                master.sendCommand(Protocol.Command.CLIENT, "UNPAUSE")
                                val publishing = CompletableFuture.runAsync { during.forEach { events.publish(it) } }
                                awaitLines(warnings)
                                warned = System.nanoTime()
                                assertTrue(!publishing.isDone, "a publish to the demoted master should wait, it ended: $publishing")
                                master.replicaofNoOne() // the URL's Redis takes writes again
                                publishing
                            }
                        }
                        publishing.get(20, TimeUnit.SECONDS)
                        val published = System.nanoTime()
                        println(
                            "[demotion${if (slow) ", slow link" else ""}] read-only WARN ${(warned - paused) / 1_000_000} ms " +
                                "after the pause; the publish waiting then returned ${(published - warned) / 1_000_000} ms after REPLICAOF NO ONE",
                        )
                        val after = (8..12).toList()
                        after.forEach { events.publish(it) }
                        val arrived = (1..during.size + after.size).map { doubled.take(Duration.ofSeconds(20)).orElseThrow() }
                        assertEquals((during + after).map { 2 * it }, arrived, "lost, duplicated or reordered around the demotion")
                        assertTrue(doubled.take(Duration.ofMillis(300)).isEmpty, "a value arrived twice")
                        assertEquals(0L, core.redisResets(), "the demoted master kept its data")
                        val lines = warnings()
                        assertEquals(1, lines.size, "read-only replica WARN lines: $lines")
                        assertTrue("give the URL of the master" in lines.single(), lines.single())
                    }
                }
            }
        }
    }

    /** Until [replica] has every write of [master] (bounded: 10 s). */
    private fun awaitInSync(master: Jedis, replica: Jedis) {
        val pause = CountDownLatch(1)
        val deadline = System.nanoTime() + Duration.ofSeconds(10).toNanos()
        fun field(info: String, name: String) = info.lines().firstOrNull { it.startsWith("$name:") }?.substringAfter(':')?.trim()
        while (System.nanoTime() < deadline) {
            val offset = field(master.info("replication"), "master_repl_offset")
            val replicaInfo = replica.info("replication")
            if (field(replicaInfo, "master_link_status") == "up" && field(replicaInfo, "slave_repl_offset") == offset) return
            pause.await(20, TimeUnit.MILLISECONDS) // a bounded poll of a state only Redis shows
        }
        throw AssertionError("the replica did not catch up with its master within 10 s: ${replica.info("replication")}")
    }

    /** Until [lines] gives a line (bounded: 10 s); a bounded poll of the log, which the core writes. */
    private fun awaitLines(lines: () -> List<String>) {
        val pause = CountDownLatch(1)
        val deadline = System.nanoTime() + Duration.ofSeconds(10).toNanos()
        while (lines().isEmpty() && System.nanoTime() < deadline) pause.await(20, TimeUnit.MILLISECONDS)
        assertTrue(lines().isNotEmpty(), "no such log line within 10 s")
    }

    /** [core]'s `start()` throws a [type] within 2 s. */
    private fun <T : Throwable> startFailsAtOnce(core: OptimusCore, type: Class<T>): T {
        val started = System.nanoTime()
        val e = assertThrows(type) { core.start() }
        val took = Duration.ofNanos(System.nanoTime() - started)
        assertTrue(took < Duration.ofSeconds(2), "start() failed after $took")
        return e
    }

    private fun core(name: String, url: String, publishTimeout: Duration = Duration.ofSeconds(2)): OptimusCore =
        OptimusCore.builder().config(CoreConfig.builder().name(name).build()).redis(url).publishTimeout(publishTimeout).build()
}

package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.conformance.CapturedStderr
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import redis.clients.jedis.args.ClientType
import redis.clients.jedis.params.ClientKillParams
import java.net.URI
import java.time.Duration
import java.util.concurrent.ConcurrentHashMap
import java.util.concurrent.ConcurrentLinkedQueue
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicBoolean
import java.util.concurrent.atomic.AtomicInteger
import java.util.concurrent.atomic.AtomicLong
import kotlin.concurrent.thread

/**
 * A failover behind one `redis://` URL, as a managed service's primary endpoint or a Sentinel
 * set-up gives it: a master and its replica (both real `redis-server` processes, append-only file
 * synced on every write), and a loopback proxy in front of the master whose URL is all the core
 * knows. Mid-stream, at the worst moment (the replica's link was cut 300 ms before, so it lacks the
 * master's last writes), in the order Sentinel or a managed service follows: the master is killed
 * with SIGKILL; once the core has met it down (the proxy counts connections the dead master refused),
 * the replica is promoted (`REPLICAOF NO ONE`); then the endpoint follows it (the proxy connects
 * to the promoted replica and drops every open connection, as a DNS flip with the old connections
 * gone); then the killed master comes back and is made the new master's replica, so that
 * [OptimusCore.Builder.replicaAcks] of 1 is confirmed again.
 *
 * With `replicaAcks(1)` every value whose publish returned comes out of the service once, in
 * order; publishes that gave up meanwhile are published again by the test (counted). No Redis
 * reset is seen (the replica had everything the core was told is stored), and the read-only
 * replica WARN never fires (the core never reaches the demoted master: the endpoint moved off it
 * before it came back).
 */
class SingleEndpointFailoverTest {

    @Test
    fun aKilledMasterBehindOneUrlIsReplacedByItsReplicaAndNoAcceptedValueIsLost() {
        EmbeddedRedis.builder().arguments(*AOF_ALWAYS).start().use { master ->
            EmbeddedRedis.builder().arguments(*AOF_ALWAYS, "--replicaof", "127.0.0.1", master.port.toString()).start().use { replica ->
                awaitLinkUp(replica)
                FaultProxy(master.uri).use { endpoint ->
                    CapturedStderr().use { err ->
                        run(master, replica, endpoint, err)
                    }
                }
            }
        }
    }

    private fun run(master: EmbeddedRedis, replica: EmbeddedRedis, endpoint: FaultProxy, err: CapturedStderr) {
        val name = "one-url-failover"
        val config = CoreConfig.builder().name(name).sourceRetention(100_000).build()
        OptimusCore.builder().config(config).redis(endpoint.url).replicaAcks(1)
            .publishTimeout(Duration.ofSeconds(PUBLISH_TIMEOUT_S)).build().use { core ->
                val (source, reader) = slowDoubling(core, SERVICE_MILLIS)
                core.start()

                val accepted = ConcurrentHashMap<Int, Long>() // value -> when its publish returned
                val retried = ConcurrentHashMap.newKeySet<Int>() // values with a publish that threw
                val thrown = AtomicInteger()
                val publishFailures = ConcurrentHashMap.newKeySet<String>()
                val arrivals = ConcurrentHashMap<Int, AtomicInteger>()
                val order = ConcurrentLinkedQueue<Int>()
                val killedAt = AtomicLong(Long.MAX_VALUE)
                val firstThroughAfterKill = AtomicLong()
                val publishedAfterKill = ConcurrentHashMap.newKeySet<Int>()
                val stopPublishing = AtomicBoolean()
                val stopReading = AtomicBoolean()
                val beforeKill = CountDownLatch(BEFORE_KILL)
                val afterFailover = CountDownLatch(AFTER_FAILOVER)
                val failedOver = AtomicBoolean()
                val readerFailures = AtomicInteger()
                val lastArrivalAt = AtomicLong(System.nanoTime())

                val publisher = thread(name = "one-url-publisher") {
                    var value = 0
                    while (!stopPublishing.get() && value < MAX_VALUES) {
                        value++
                        val begunAfterKill = System.nanoTime() > killedAt.get()
                        var attempts = 0
                        while (!stopPublishing.get() && attempts < MAX_ATTEMPTS) {
                            attempts++
                            try {
                                core.publishAll(source, listOf(value))
                                accepted[value] = System.nanoTime()
                                if (begunAfterKill) publishedAfterKill += value
                                beforeKill.countDown()
                                if (failedOver.get()) afterFailover.countDown()
                                break
                            } catch (e: Exception) {
                                thrown.incrementAndGet()
                                retried += value
                                publishFailures += e.javaClass.simpleName
                            }
                        }
                    }
                }
                val consumer = thread(name = "one-url-reader") {
                    while (!stopReading.get()) {
                        val next = try {
                            reader.take(Duration.ofMillis(200))
                        } catch (_: Exception) {
                            readerFailures.incrementAndGet()
                            continue // Redis unreachable for a moment: take again
                        }
                        next.ifPresent { doubledValue ->
                            val value = doubledValue / 2
                            arrivals.computeIfAbsent(value) { AtomicInteger() }.incrementAndGet()
                            order += value
                            lastArrivalAt.set(System.nanoTime())
                            if (value in publishedAfterKill) firstThroughAfterKill.compareAndSet(0, System.nanoTime())
                        }
                    }
                }
                try {
                    assertTrue(beforeKill.await(PATIENCE_S, TimeUnit.SECONDS), "values flow before the kill")
                    val lag = cutReplicationLink(master, replica, Duration.ofMillis(CUT_MILLIS))
                    val refusedBefore = endpoint.refusedConnects.get()
                    killedAt.set(System.nanoTime())
                    master.kill() // SIGKILL: no save, no goodbye to the clients
                    // the core meets the dead master through the endpoint before anything moves
                    awaitTrue("the core reconnects to the dead master and is refused") { endpoint.refusedConnects.get() > refusedBefore }
                    val metDownAt = System.nanoTime()
                    Jedis(URI(replica.uri)).use { it.replicaofNoOne() } // Sentinel or the service promotes the replica
                    val promotedAt = System.nanoTime()
                    endpoint.switchTo(replica.uri) // then the endpoint follows it; old connections are gone
                    val switchedAt = System.nanoTime()
                    master.restart() // a supervisor starts the killed server again, from its AOF
                    Jedis(URI(master.uri)).use { it.replicaof("127.0.0.1", replica.port) } // made the new master's replica
                    awaitLinkUp(master)
                    val rejoinedAt = System.nanoTime()
                    failedOver.set(true)
                    assertTrue(afterFailover.await(PATIENCE_S, TimeUnit.SECONDS), "values flow after the failover")
                    stopPublishing.set(true)
                    publisher.join(TimeUnit.SECONDS.toMillis(PATIENCE_S))
                    assertTrue(!publisher.isAlive, "the publisher ended")
                    lastArrivalAt.set(System.nanoTime()) // the quiet counts from the last publish on

                    // until every accepted value arrived, or none arrived for a while (bounded): what is missing then is lost
                    val arrivalDeadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(PATIENCE_S)
                    while (accepted.keys.any { !arrivals.containsKey(it) } && System.nanoTime() < arrivalDeadline &&
                        System.nanoTime() - lastArrivalAt.get() < TimeUnit.SECONDS.toNanos(QUIET_S)
                    ) {
                        Thread.sleep(POLL_MILLIS)
                    }
                    stopReading.set(true)
                    consumer.join(TimeUnit.SECONDS.toMillis(PATIENCE_S))
                    assertTrue(!consumer.isAlive, "the reader ended")

                    val lost = accepted.keys.filter { !arrivals.containsKey(it) }.sorted()
                    // a publish that threw may have stored its value before giving up; its retry stores it again
                    val duplicated = arrivals.filter { (value, n) -> n.get() > 1 && value !in retried }.keys.sorted()
                    val twiceAfterAThrow = arrivals.filter { (value, n) -> n.get() > 1 && value in retried }.keys.sorted()
                    var highest = 0
                    var reordered = 0
                    for (value in order) {
                        if (value < highest) reordered++ else highest = value
                    }
                    val unknown = arrivals.keys.filter { !accepted.containsKey(it) }.sorted()
                    val warnings = err.lines().filter { " WARN " in it }
                    val recovery = firstThroughAfterKill.get().takeIf { it != 0L }?.let { seconds(it - killedAt.get()) }
                    println(
                        "one-url failover: replica $lag bytes behind at the kill; ${accepted.size} values accepted, " +
                            "${lost.size} lost ${ranges(lost)}, ${duplicated.size} duplicated, " +
                            "$reordered reordered; ${thrown.get()} publishes threw and were retried ($publishFailures, " +
                            "${retried.size} values, ${twiceAfterAThrow.size} of them arrived twice); ${readerFailures.get()} reads threw; " +
                            "down met ${seconds(metDownAt - killedAt.get())} s, replica promoted ${seconds(promotedAt - killedAt.get())} s, " +
                            "endpoint switched ${seconds(switchedAt - killedAt.get())} s, old master a replica " +
                            "${seconds(rejoinedAt - killedAt.get())} s and first value published after the kill out $recovery s " +
                            "after the kill; Redis resets ${core.redisResets()}; ${warnings.size} WARN lines:\n" +
                            warnings.joinToString("\n"),
                    )
                    assertEquals("[]", ranges(lost), "accepted values lost in the failover")
                    assertEquals("[]", ranges(duplicated), "accepted values the reader got twice")
                    assertEquals(0, reordered, "values that arrived after a later one")
                    assertEquals(emptyList<Int>(), unknown, "values that arrived but were never accepted")
                    assertTrue(recovery != null, "a value published after the kill came through")
                    assertEquals(0L, core.redisResets(), "Redis resets: the promoted replica had everything the core was told")
                    assertEquals(0, core.deadLetters("double").size, "dead letters")
                    val readOnly = warnings.filter { "read-only replica" in it }
                    assertEquals(emptyList<String>(), readOnly, "read-only replica WARN lines")
                    val unexpected = warnings.filter { name !in it || !EXPECTED_WARNINGS.any { w -> w in it } }
                    assertEquals(emptyList<String>(), unexpected, "WARN lines other than an outage's")
                } finally {
                    stopPublishing.set(true)
                    stopReading.set(true)
                    publisher.join(TimeUnit.SECONDS.toMillis(PATIENCE_S))
                    consumer.join(TimeUnit.SECONDS.toMillis(PATIENCE_S))
                }
            }
    }

    /**
     * Cuts [replica] off [master] (a bogus `masterauth` fails its handshake, `CLIENT KILL TYPE
     * replica` drops the link), then lets [master] run ahead for [window] (the fault's length, not
     * a wait for anything) once it wrote past what the replica got; returns by how many bytes the
     * replica is behind.
     */
    private fun cutReplicationLink(master: EmbeddedRedis, replica: EmbeddedRedis, window: Duration): Long {
        Jedis(URI(replica.uri)).use { it.configSet("masterauth", "no-such-password") }
        Jedis(URI(master.uri)).use { it.clientKill(ClientKillParams().type(ClientType.REPLICA)) }
        val got = Jedis(URI(replica.uri)).use { offset(it.info("replication"), "master_repl_offset") }
        val masterOffset = { Jedis(URI(master.uri)).use { offset(it.info("replication"), "master_repl_offset") } }
        awaitTrue("the master writes past the offset $got of its cut-off replica") { masterOffset() > got }
        Thread.sleep(window.toMillis())
        return masterOffset() - got
    }

    private fun offset(info: String, field: String): Long =
        info.lines().first { it.startsWith("$field:") }.substringAfter(':').trim().toLong()

    /** Waits until [redis] is a replica whose link to its master is up and synced. */
    private fun awaitLinkUp(redis: EmbeddedRedis) {
        awaitTrue("${redis.uri} replicates its master") {
            try {
                Jedis(URI(redis.uri)).use { "master_link_status:up" in it.info("replication") }
            } catch (_: Exception) {
                false
            }
        }
    }

    private fun awaitTrue(what: String, condition: () -> Boolean) {
        val deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(PATIENCE_S)
        while (!condition()) {
            assertTrue(System.nanoTime() < deadline, "within $PATIENCE_S s: $what")
            Thread.sleep(POLL_MILLIS)
        }
    }

    /** [sorted] as ranges, "[3..7, 9]". */
    private fun ranges(sorted: List<Int>): String {
        val parts = mutableListOf<String>()
        var i = 0
        while (i < sorted.size) {
            var j = i
            while (j + 1 < sorted.size && sorted[j + 1] == sorted[j] + 1) j++
            parts += if (j > i) "${sorted[i]}..${sorted[j]}" else "${sorted[i]}"
            i = j + 1
        }
        return parts.joinToString(", ", "[", "]")
    }

    private fun seconds(nanos: Long) = "%.2f".format(nanos / 1e9)

    private companion object {
        val AOF_ALWAYS = arrayOf("--appendonly", "yes", "--appendfsync", "always")

        /** What a core logs in an outage: its service lost Redis, its heartbeat failed (no master, or no replica confirmed). */
        val EXPECTED_WARNINGS = listOf("service 'double' lost Redis", "the heartbeat of instance")
        const val PATIENCE_S = 20L
        const val PUBLISH_TIMEOUT_S = 2L
        const val CUT_MILLIS = 300L
        const val QUIET_S = 3L
        const val BEFORE_KILL = 200
        const val AFTER_FAILOVER = 200
        const val MAX_VALUES = 100_000
        const val MAX_ATTEMPTS = 20
        const val SERVICE_MILLIS = 3L
        const val POLL_MILLIS = 20L
    }
}

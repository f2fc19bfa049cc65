package dev.prime.optimus

import dev.prime.Reader
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration
import java.util.Optional
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicInteger
import kotlin.concurrent.thread

/**
 * [Hosting.UNORDERED]: several hosts take from one service's input at once; every value's result
 * is stored once, the queue depth counts every host's processing list, and a host killed with
 * SIGKILL in the middle of a flow loses nothing: a survivor moves what it held back to the input.
 */
class CompetingConsumersTest {

    @Test
    fun threeHostsShareTheInputAndEveryValueIsProcessedOnce() {
        val name = "competing-three"
        val n = 300
        val counts = List(3) { AtomicInteger() }
        val hosts = counts.map { count ->
            CompetingTopology.core(TestRedis.url, name, Hosting.UNORDERED).also { core ->
                CompetingTopology.declare(core, 2) { count.incrementAndGet() }
            }
        }
        try {
            CompetingTopology.core(TestRedis.url, name, null).use { publisher ->
                val (numbers, output) = CompetingTopology.declare(publisher, 0)
                val reader = output.reader()
                publisher.start()
                hosts.forEach { it.start() }
                hosts.forEach { assertEquals(setOf(CompetingTopology.SERVICE), it.serviceNames(), "every host runs the service") }
                (0 until n).forEach(numbers::publish)
                val received = takeAll(reader, n)
                assertEquals((0 until n).toList(), received.sorted(), "0 lost, 0 duplicated")
                assertEquals(Optional.empty<Int>(), reader.poll())
                assertEquals(n, counts.sumOf { it.get() }, "each block ran once per value: ${counts.map { it.get() }}")
                counts.forEach { assertTrue(it.get() >= n / 10, "every host took a share: ${counts.map { c -> c.get() }}") }
                Jedis(URI(TestRedis.url)).use { jedis ->
                    assertEquals(n.toLong(), TestRedis.values(jedis, publisher.keys.sourceLog(output.name())), "each result stored once")
                }
            }
        } finally {
            hosts.forEach { it.close() }
        }
    }

    @Test
    fun callsToAnUnorderedServiceAreSharedByItsHostsAndEachAnswered() {
        val name = "competing-calls"
        fun core(hosting: Boolean) = OptimusCore.builder().config(dev.prime.CoreConfig.builder().name(name).build())
            .redis(TestRedis.url).leaseTime(CompetingTopology.LEASE)
            .let { if (hosting) it.hosts("square").hosting("square", Hosting.UNORDERED) else it.hosts(emptyList()) }
            .build()
        val counts = List(2) { AtomicInteger() }
        val hosts = counts.map { count ->
            core(true).also { host ->
                host.chain("square") { x: Int ->
                    count.incrementAndGet()
                    Thread.sleep(5)
                    x * x
                }.toBlock()
            }
        }
        try {
            core(false).use { caller ->
                val square = caller.chain("square") { x: Int -> x * x }.toBlock()
                caller.start()
                hosts.forEach { it.start() }
                val callers = (0 until 4).map { t ->
                    java.util.concurrent.CompletableFuture.supplyAsync {
                        (0 until 25).map { i -> (t * 25 + i).let { x -> square.process(x) == x * x } }
                    }
                }
                val answers = callers.flatMap { it.get(PATIENCE.seconds, TimeUnit.SECONDS) }
                assertEquals(List(100) { true }, answers, "every call got its own answer")
                assertEquals(100, counts.sumOf { it.get() }, "each request processed once: ${counts.map { it.get() }}")
                counts.forEach { assertTrue(it.get() > 0, "both hosts answered calls: ${counts.map { c -> c.get() }}") }
            }
        } finally {
            hosts.forEach { it.close() }
        }
    }

    @Test
    fun queueDepthCountsTheProcessingListOfEveryHost() {
        val name = "competing-depth"
        val gate = CountDownLatch(1)
        val entered = CountDownLatch(3)
        val hosts = (0 until 3).map {
            CompetingTopology.core(TestRedis.url, name, Hosting.UNORDERED).also { core ->
                CompetingTopology.declare(core, 0) {
                    entered.countDown()
                    gate.await(PATIENCE.seconds, TimeUnit.SECONDS)
                }
            }
        }
        try {
            CompetingTopology.core(TestRedis.url, name, null).use { publisher ->
                val (numbers, output) = CompetingTopology.declare(publisher, 0)
                val reader = output.reader()
                publisher.start()
                hosts.forEach { it.start() }
                (0 until 10).forEach(numbers::publish)
                assertTrue(entered.await(PATIENCE.seconds, TimeUnit.SECONDS), "each host holds a value in its block")
                Jedis(URI(TestRedis.url)).use { jedis ->
                    hosts.forEach { host ->
                        assertEquals(1L, jedis.llen(publisher.keys.hostProcessing(CompetingTopology.SERVICE, host.instanceId)))
                    }
                }
                assertEquals(10L, RedisServiceGauges(publisher).queueDepth(CompetingTopology.SERVICE), "3 held by hosts + 7 waiting")
                gate.countDown()
                assertEquals((0 until 10).toList(), takeAll(reader, 10).sorted())
                assertEquals(0L, RedisServiceGauges(publisher).queueDepth(CompetingTopology.SERVICE))
            }
        } finally {
            gate.countDown()
            hosts.forEach { it.close() }
        }
    }

    @Test
    fun aHostKilledMidFlowLosesNothingAndASurvivorReclaimsWithinTheLease() {
        val name = "competing-kill"
        val n = 300
        EmbeddedRedis.start().use { redis ->
            CompetingTopology.core(redis.uri, name, null).use { publisher ->
                val (numbers, output) = CompetingTopology.declare(publisher, 0)
                val reader = output.reader()
                publisher.start()
                val keys = publisher.keys
                val args = arrayOf(redis.uri, name, "UNORDERED", "10")
                WorkerProcess.start(ConsumerWorkerMain::class.java, *args).use { victim ->
                    WorkerProcess.start(ConsumerWorkerMain::class.java, *args).use { survivor ->
                        val victimId = victim.awaitLine("READY").substringAfter(' ')
                        survivor.awaitLine("READY")
                        val publishing = thread(name = "competing-kill-publisher") { (0 until n).forEach(numbers::publish) }
                        try {
                            val received = takeAll(reader, n / 3)
                            Jedis(URI(redis.uri)).use { jedis ->
                                victim.kill()
                                val killed = System.nanoTime()
                                val held = TestRedis.values(jedis, keys.hostProcessing(CompetingTopology.SERVICE, victimId))
                                assertTrue(held > 0, "the killed host held values it had taken and not stored: $held")
                                val hostsKey = keys.serviceHosts(CompetingTopology.SERVICE)
                                val reclaimed = boundedWait(Duration.ofSeconds(10)) {
                                    !jedis.sismember(hostsKey, victimId.toByteArray(UTF_8))
                                }
                                val seconds = (System.nanoTime() - killed) / 1e9
                                println("CompetingConsumersTest: a survivor reclaimed the $held value(s) of the killed host %.2f s after the kill".format(seconds))
                                assertTrue(reclaimed && seconds <= 3.0, "reclaimed within the lease and a beat (1.33 s), bounded: $seconds s")
                                received += takeAll(reader, n - n / 3)
                                val lost = (0 until n).toSet() - received.toSet()
                                assertEquals(emptySet<Int>(), lost, "0 lost")
                                assertEquals(Optional.empty<Int>(), reader.poll())
                                val stored = TestRedis.values(jedis, keys.sourceLog(output.name()))
                                assertEquals(n.toLong(), stored, "0 duplicated: each result stored once (${stored - n} extra)")
                                assertEquals(0L, jedis.llen(keys.hostProcessing(CompetingTopology.SERVICE, victimId)), "nothing left behind")
                            }
                            survivor.send("STOP")
                            val processed = survivor.awaitLine("PROCESSED").substringAfter(' ').toInt()
                            assertTrue(processed in 1 until n, "the survivor processed a share ($processed), the victim the rest")
                        } finally {
                            publishing.join(PATIENCE.toMillis())
                        }
                    }
                }
            }
        }
    }

    @Test
    fun aHostWhoseSeatLapsedStoresNothingOfWhatItHeldAndStartsANewRun() {
        val name = "competing-lapse"
        val gate = CountDownLatch(1)
        val entered = CountDownLatch(1)
        val returned = CountDownLatch(1)
        val first = java.util.concurrent.atomic.AtomicBoolean(true)
        val runs = AtomicInteger()
        val frozen = CompetingTopology.core(TestRedis.url, name, Hosting.UNORDERED)
        CompetingTopology.declare(frozen, 0) {
            runs.incrementAndGet()
            if (first.getAndSet(false)) { // the first value: this host "freezes" in it
                entered.countDown()
                gate.await(PATIENCE.seconds, TimeUnit.SECONDS)
                returned.countDown()
            }
        }
        val other = CompetingTopology.core(TestRedis.url, name, Hosting.UNORDERED)
        CompetingTopology.declare(other, 0) { runs.incrementAndGet() }
        try {
            CompetingTopology.core(TestRedis.url, name, null).use { publisher ->
                val (numbers, output) = CompetingTopology.declare(publisher, 0)
                val reader = output.reader()
                publisher.start()
                frozen.start()
                numbers.publish(0)
                assertTrue(entered.await(PATIENCE.seconds, TimeUnit.SECONDS))
                other.start()
                Jedis(URI(TestRedis.url)).use { jedis ->
                    // its seat lapses, as after a freeze longer than the lease: the value it holds goes to another run
                    jedis.del(publisher.keys.hostSeatLease(CompetingTopology.SERVICE, frozen.instanceId))
                    assertEquals(listOf(0), takeAll(reader, 1), "the held value is processed by another run")
                    gate.countDown()
                    assertTrue(returned.await(PATIENCE.seconds, TimeUnit.SECONDS))
                    (1..20).forEach(numbers::publish)
                    assertEquals((1..20).toList(), takeAll(reader, 20).sorted())
                    assertEquals(Optional.empty<Int>(), reader.poll())
                    assertEquals(21L, TestRedis.values(jedis, publisher.keys.sourceLog(output.name())), "value 0 was stored once")
                    assertEquals(22, runs.get(), "value 0's block ran twice (the lapsed run's result was fenced), the others once")
                    assertEquals(setOf(CompetingTopology.SERVICE), frozen.serviceNames(), "the lapsed host runs the service again")
                }
            }
        } finally {
            gate.countDown()
            frozen.close()
            other.close()
        }
    }

    internal companion object {
        val PATIENCE: Duration = Duration.ofSeconds(20)

        fun takeAll(reader: Reader<Int>, n: Int): MutableList<Int> = (0 until n).mapTo(ArrayList()) { i ->
            reader.take(PATIENCE).orElseThrow { AssertionError("value ${i + 1} of $n did not arrive within $PATIENCE") }
        }

        /** Checks [condition] every 10 ms until it holds or [limit] passed; whether it held. */
        fun boundedWait(limit: Duration, condition: () -> Boolean): Boolean {
            val deadline = System.nanoTime() + limit.toNanos()
            while (System.nanoTime() < deadline) {
                if (condition()) return true
                Thread.sleep(10)
            }
            return condition()
        }
    }
}

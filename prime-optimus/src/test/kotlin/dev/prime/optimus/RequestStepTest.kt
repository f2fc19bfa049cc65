package dev.prime.optimus

import dev.prime.Block
import dev.prime.CoreConfig
import dev.prime.PrimeException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.assertThrows
import redis.clients.jedis.Jedis
import redis.clients.jedis.params.SetParams
import java.net.URI
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration
import java.util.concurrent.CompletableFuture
import java.util.concurrent.CountDownLatch
import java.util.concurrent.Executors
import java.util.concurrent.TimeUnit

/**
 * The step of a service only called, for a lone request ([RequestStep]: a transaction its take
 * watched, or [Script.REQUEST_STEP]), keeps the general step's promises: it is what a call's
 * service runs (a handful of plain commands, counted here on a Redis of its own), it is fenced by
 * the host lease (a host whose lease another instance took stores nothing and stops; a lease held by nobody is waited for, then the reply is
 * stored once), a reply key of the wrong type leaves it untouched for the general step to
 * dead-letter, and a chain of several services forwards the request with it.
 */
class RequestStepTest {

    @Test
    fun aCallCostsATransactionOfPlainCommandsAndTheCommandsOfAPushAndAPop() {
        EmbeddedRedis.start().use { redis ->
            // a long lease: no heartbeat during the calls (a renewal would make one step go through the script)
            OptimusCore.builder().config(named("request-step-count")).redis(redis.uri).leaseTime(LONG_LEASE).build().use { core ->
                val echo: Block<Int, Int> = core.chain("echo") { x: Int -> x + 1 }.toBlock()
                core.start()
                assertEquals(2, echo.process(1), "warm: the reply list exists and the service's take is watched")
                Jedis(URI(redis.uri)).use { jedis ->
                    jedis.configResetStat()
                    val started = System.nanoTime()
                    for (i in 1..CALLS) assertEquals(i + 1, echo.process(i))
                    val seconds = Duration.ofNanos(System.nanoTime() - started).toSeconds()
                    val calls = commandCalls(jedis)
                    assertEquals(null, calls["evalsha"], "no script on the call path: $calls")
                    assertEquals(null, calls["eval"], "no script on the call path: $calls")
                    // the step: a transaction of plain commands; the caller: clear, push, wait
                    for (command in listOf("multi", "exec", "lmove", "lset", "pexpire", "del", "rpush")) {
                        assertEquals(CALLS.toLong(), calls[command], "one $command per call: $calls")
                    }
                    // the caller's wait and the service's take; a take that waited a whole poll slice (1 s) counts too,
                    // and the one the service was blocked in when the count was reset may fall on either side of it
                    val moves = calls.getValue("blmove")
                    assertTrue(moves in 2L * CALLS - 1..2L * CALLS + 2 * (seconds + 1), "two blocking moves per call: $calls")
                    // behind each take of the service (answered with it): WATCH of the lease, GET of it, two lengths
                    val takes = CALLS.toLong()..CALLS + 2 * (seconds + 1)
                    assertTrue(calls.getValue("watch") in takes && calls.getValue("get") in takes, "one WATCH and GET per take: $calls")
                    assertEquals(2 * calls.getValue("watch"), calls["llen"], "two lengths per take: $calls")
                    val other = calls.keys - setOf("multi", "exec", "lmove", "lset", "pexpire", "watch", "get", "del", "rpush", "blmove", "llen", "unwatch", "config|resetstat")
                    assertEquals(emptySet<String>(), other, "nothing else per call: $calls")
                }
            }
        }
    }

    @Test
    fun aCalledServiceWhoseLeaseAnotherInstanceTookRepliesNothingAndStops() {
        val name = "request-step-fence-taken"
        val keys = Keys(name)
        val reported = CompletableFuture<Throwable>()
        val config = CoreConfig.builder().name(name).errorHandler { _, _, error -> reported.complete(error) }.build()
        val entered = CountDownLatch(1)
        val release = CountDownLatch(1)
        val caller = Executors.newSingleThreadExecutor()
        try {
            Jedis(URI(TestRedis.url)).use { jedis ->
                OptimusCore.builder().config(config).redis(TestRedis.url).leaseTime(LONG_LEASE).callTimeout(CALL_TIMEOUT).build().use { host ->
                    val double: Block<Int, Int> = host.chain("double") { x: Int ->
                        entered.countDown()
                        check(release.await(PATIENCE.seconds, TimeUnit.SECONDS)) { "the test did not release the block" }
                        2 * x
                    }.toBlock()
                    host.start()
                    val call = caller.submit<Int> { double.process(21) }
                    assertTrue(entered.await(PATIENCE.seconds, TimeUnit.SECONDS), "the service took the request")
                    jedis.set(keys.hostLease("double"), "intruder".toByteArray(UTF_8), SetParams().px(Duration.ofMinutes(1).toMillis()))
                    release.countDown()

                    val error = reported.get(PATIENCE.seconds, TimeUnit.SECONDS)
                    assertTrue(error is IllegalStateException && error.message!!.contains("instance intruder"), error.toString())
                    assertFalse("double" in host.serviceNames(), "the service is stopped")
                    val failure = assertThrows<java.util.concurrent.ExecutionException> { call.get(PATIENCE.seconds, TimeUnit.SECONDS) }
                    assertTrue(failure.cause is PrimeException && "did not reply" in failure.cause!!.message!!, failure.cause.toString())
                    val held = jedis.lrange(keys.serviceProcessing("double"), 0, -1)
                    assertEquals(1, held.size, "the request stays in the processing list for the new host")
                    assertEquals(Envelope.Kind.REQUEST, Envelope.parse(held[0]).kind)
                    assertEquals(0L, jedis.llen(keys.deadLetters("double")), "no dead letter")
                    assertEquals("intruder", jedis.get(keys.hostLease("double"))?.toString(UTF_8), "the other's lease is left alone")
                }
            }
        } finally {
            caller.shutdownNow()
        }
    }

    @Test
    fun aCalledServiceThatFindsItsLeaseHeldByNobodyReadsItsListAgainAndRepliesOnce() {
        val name = "request-step-fence-lapsed"
        val keys = Keys(name)
        val entered = CountDownLatch(1)
        val release = CountDownLatch(1)
        val runs = java.util.concurrent.atomic.AtomicInteger()
        val caller = Executors.newSingleThreadExecutor()
        try {
            Jedis(URI(TestRedis.url)).use { jedis ->
                val config = CoreConfig.builder().name(name).build()
                OptimusCore.builder().config(config).redis(TestRedis.url).leaseTime(SHORT_LEASE).callTimeout(PATIENCE).build().use { host ->
                    val double: Block<Int, Int> = host.chain("double") { x: Int ->
                        runs.incrementAndGet()
                        entered.countDown()
                        check(release.await(PATIENCE.seconds, TimeUnit.SECONDS)) { "the test did not release the block" }
                        2 * x
                    }.toBlock()
                    host.start()
                    val call = caller.submit<Int> { double.process(21) }
                    assertTrue(entered.await(PATIENCE.seconds, TimeUnit.SECONDS), "the service took the request")
                    assertEquals(1L, jedis.del(keys.hostLease("double")), "nobody holds the lease now")
                    release.countDown()
                    assertEquals(42, call.get(PATIENCE.seconds, TimeUnit.SECONDS), "the reply came once the lease was re-claimed")
                    // the step stored nothing (another host might have held the lease meanwhile): the service read its
                    // processing list again, re-claiming the lease, and ran the request once more
                    assertEquals(2, runs.get(), "the request was run again after the lapse, its first result not stored")
                    assertEquals(8, double.process(4), "the service goes on")
                    assertEquals(3, runs.get(), "the next request ran once")
                    assertEquals(0L, jedis.llen(keys.serviceProcessing("double")), "everything acknowledged")
                    assertEquals(host.instanceId, jedis.get(keys.hostLease("double"))?.toString(Charsets.UTF_8), "the service re-claimed the lease")
                }
            }
        } finally {
            caller.shutdownNow()
        }
    }

    @Test
    fun aLoneRequestWhoseReplyKeyIsNotAListIsDeadLetteredByTheGeneralStep() {
        val entered = CountDownLatch(1)
        val release = CountDownLatch(1)
        val caller = Executors.newSingleThreadExecutor()
        try {
            OptimusCore.builder().config(named("request-step-refused")).redis(TestRedis.url).callTimeout(PATIENCE).build().use { core ->
                val echo: Block<Int, Int> = core.chain("echo") { x: Int ->
                    if (x == 1) {
                        entered.countDown()
                        check(release.await(PATIENCE.seconds, TimeUnit.SECONDS)) { "the test did not release the block" }
                    }
                    x
                }.toBlock()
                core.start()
                val first = caller.submit<Int> { echo.process(1) }
                assertTrue(entered.await(PATIENCE.seconds, TimeUnit.SECONDS), "the service took the first request")
                val wrongKind = core.keys.reply("a-string")
                Jedis(URI(TestRedis.url)).use { raw ->
                    raw.set(wrongKind, "a string".toByteArray())
                    // the first request's step takes it, alone: the next step is the request step of that one request
                    raw.rpush(core.keys.serviceInput("echo"), Envelope.request(ValueIds().next(), wrongKind, core.encode(7)))
                    release.countDown()
                    assertEquals(1, first.get(PATIENCE.seconds, TimeUnit.SECONDS))
                    assertEquals(5, echo.process(5), "the service still serves (after the bad request, in order)")
                    val reasons = core.deadLetters("echo").map { it.reason }
                    assertEquals(1, reasons.size, reasons.toString())
                    assertTrue("not a reply list" in reasons[0], reasons[0])
                    assertEquals("a string", raw.get(wrongKind)?.toString(UTF_8), "the key is left as it was")
                    assertEquals(0L, raw.llen(core.keys.serviceProcessing("echo")), "everything acknowledged")
                }
            }
        } finally {
            caller.shutdownNow()
        }
    }

    @Test
    fun manyCallersThroughAChainOfThreeEachGetTheirOwnReplyOnce() {
        OptimusCore.builder().config(named("request-step-chain")).redis(TestRedis.url).callTimeout(PATIENCE).build().use { core ->
            val runs = java.util.concurrent.ConcurrentHashMap<Int, Int>()
            val chain = core.link(
                core.link(core.chain("first") { x: Int -> runs.merge(x, 1, Int::plus); x + 1 }, core.chain("second") { x: Int -> x * 2 }),
                core.chain("third") { x: Int -> x - 1 },
            )
            val block: Block<Int, Int> = chain.toBlock()
            core.start()
            val pool = Executors.newFixedThreadPool(CALLERS)
            try {
                val results = (0 until CALLERS).map { c ->
                    pool.submit<List<Int>> { (0 until CALLS).map { i -> block.process(c * 1000 + i) } }
                }.map { it.get(PATIENCE.seconds * 2, TimeUnit.SECONDS) }
                results.forEachIndexed { c, got ->
                    assertEquals((0 until CALLS).map { i -> (c * 1000 + i + 1) * 2 - 1 }, got, "caller $c")
                }
            } finally {
                pool.shutdownNow()
            }
            assertEquals(CALLERS * CALLS, runs.size, "every request reached the chain")
            assertTrue(runs.values.all { it == 1 }, "each once: ${runs.filterValues { it != 1 }}")
            Jedis(URI(TestRedis.url)).use { raw ->
                for (service in listOf("first", "second", "third")) {
                    assertEquals(0L, raw.llen(core.keys.serviceProcessing(service)), "$service acknowledged everything")
                    assertEquals(0L, raw.llen(core.keys.deadLetters(service)), "$service dead-lettered nothing")
                }
            }
        }
    }

    private fun named(name: String): CoreConfig = CoreConfig.builder().name(name).build()

    /** Calls per command since the last `CONFIG RESETSTAT`, from `INFO commandstats`. */
    private fun commandCalls(jedis: Jedis): Map<String, Long> =
        jedis.info("commandstats").lines().filter { it.startsWith("cmdstat_") }.associate { line ->
            line.substring("cmdstat_".length, line.indexOf(':')) to line.substringAfter("calls=").substringBefore(',').toLong()
        }

    private companion object {
        const val CALLS = 50
        const val CALLERS = 8
        val LONG_LEASE: Duration = Duration.ofSeconds(30)
        val SHORT_LEASE: Duration = Duration.ofSeconds(3)
        val CALL_TIMEOUT: Duration = Duration.ofSeconds(3)
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

package dev.prime.optimus

import dev.prime.Block
import dev.prime.CoreConfig
import org.junit.jupiter.api.AfterEach
import org.junit.jupiter.api.Assertions.assertArrayEquals
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.BeforeEach
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.assertThrows
import redis.clients.jedis.Jedis
import redis.clients.jedis.exceptions.JedisConnectionException
import redis.clients.jedis.params.SetParams
import java.net.URI
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration
import java.util.concurrent.atomic.AtomicInteger

/**
 * The step of a lone request without the script ([RequestStep.storeWatched]): a transaction of
 * plain commands that the `WATCH` written behind the request's take guards. It stores the reply
 * and acknowledges the request only while the host lease is untouched since that take: a lease
 * another instance took, one that lapsed, and one renewed since all make Redis refuse it, and it
 * then stores nothing. It is never sent on a connection other than the one that watched (a new
 * connection carries no `WATCH`), and a take that leaves anything else to store first (a
 * backlog, an entry already in the processing list, a lease not this instance's) is not watched.
 * Through a service, a renewal during the step costs nothing but the script: the reply comes once
 * and at once.
 */
class WatchedRequestStepTest {
    private lateinit var core: OptimusCore
    private lateinit var raw: Jedis
    private lateinit var step: RequestStep
    private val keys = Keys(NAME)
    private val input = keys.serviceInput("svc")
    private val processing = keys.serviceProcessing("svc")
    private val lease = keys.hostLease("svc")
    private val replyKey = keys.reply("caller")
    private val request = Envelope.request(1, replyKey, byteArrayOf(1, 2, 3))
    private val reply = Envelope.replyOk(1, byteArrayOf(4, 5, 6))

    @BeforeEach
    fun setUp() {
        core = OptimusCore.builder().config(CoreConfig.builder().name(NAME).build()).redis(TestRedis.url).build()
        raw = Jedis(URI(TestRedis.url))
        raw.del(input, processing, lease, replyKey)
        raw.set(lease, ME, SetParams().px(LEASE_MILLIS))
        step = RequestStep(processing, input, HostFence(lease, ME), core.stepRules)
        // the default user may send everything: steps may go without the script from here on
        core.connections.open().use { jedis -> assertNull(step.checkPermissions(jedis), "a refusal for the default user") }
    }

    @AfterEach
    fun tearDown() {
        raw.del(input, processing, lease, replyKey)
        raw.close()
        core.close()
    }

    @Test
    fun aWatchedStepStoresTheReplyWithItsExpiryAndAcknowledgesTheRequest() {
        core.connections.open().use { jedis ->
            raw.rpush(input, request)
            val taken = step.takeWatched(jedis, WAIT)
            assertArrayEquals(request, taken)
            assertTrue(step.isWatched(jedis, taken!!), "a lone request of a service that keeps up is watched")
            assertTrue(step.storeWatched(jedis, RequestOutput(replyKey, reply, isReply = true), WAIT))
            assertNull(step.readTakeBehind(jedis), "nothing more came")
            assertEquals(listOf(reply.toList()), raw.lrange(replyKey, 0, -1).map { it.toList() }, "the reply, once")
            assertTrue(raw.pttl(replyKey) in 1..core.stepRules.replyTtlMillis, "the reply list expires")
            assertEquals(0L, raw.llen(processing), "the request is acknowledged")
        }
    }

    @Test
    fun aStepWhoseLeaseAnotherInstanceTookSinceTheTakeStoresNothing() {
        refusedAfter { raw.set(lease, "intruder".toByteArray(UTF_8), SetParams().px(LEASE_MILLIS)) }
        assertEquals("intruder", raw.get(lease)?.toString(UTF_8), "the other's lease is left alone")
    }

    @Test
    fun aStepWhoseLeaseLapsedSinceTheTakeStoresNothing() {
        refusedAfter { raw.del(lease) }
    }

    @Test
    fun aStepWhoseLeaseWasRenewedSinceTheTakeStoresNothingEither() {
        // what the heartbeat does every third of the lease: the general step must then store it
        refusedAfter { raw.pexpire(lease, LEASE_MILLIS) }
    }

    @Test
    fun aConnectionThatWasClosedNeverCarriesTheStep() {
        val jedis = core.connections.open()
        raw.rpush(input, request)
        val taken = step.takeWatched(jedis, WAIT)!!
        core.connections.release(jedis) // Jedis would open it again, without the WATCH
        assertThrows<JedisConnectionException> { step.storeWatched(jedis, RequestOutput(replyKey, reply, isReply = true), WAIT) }
        assertFalse(raw.exists(replyKey), "no reply was stored")
        assertEquals(listOf(taken.toList()), raw.lrange(processing, 0, -1).map { it.toList() }, "the request is not acknowledged")
        core.connections.open().use { other -> assertFalse(step.isWatched(other, taken), "another connection is not watched") }
    }

    @Test
    fun aClosedConnectionFailsInsteadOfOpeningAgainWithoutWhatItHeld() {
        val jedis = core.connections.open()
        val clients = raw.clientList().lines().count { it.isNotBlank() }
        core.connections.release(jedis)
        // Jedis itself would open a new socket here, without the WATCH, the MULTI or the login of the old one
        assertThrows<JedisConnectionException> { jedis.rpush(input, request) }
        assertEquals(0L, raw.llen(input), "nothing was written")
        assertEquals(clients - 1, raw.clientList().lines().count { it.isNotBlank() }, "no connection was opened in its place")
    }

    @Test
    fun aTakeWithAnythingElseToStoreFirstIsNotWatched() {
        core.connections.open().use { jedis ->
            raw.rpush(input, request, request)
            assertFalse(step.isWatched(jedis, step.takeWatched(jedis, WAIT)!!), "a backlog: the script takes it in batches")
            raw.del(input)
            raw.rpush(input, request)
            assertFalse(step.isWatched(jedis, step.takeWatched(jedis, WAIT)!!), "the processing list holds more than the taken entry")
            raw.del(input, processing)
            raw.rpush(input, request)
            raw.set(lease, "intruder".toByteArray(UTF_8), SetParams().px(LEASE_MILLIS))
            assertFalse(step.isWatched(jedis, step.takeWatched(jedis, WAIT)!!), "the lease is another instance's")
            assertNull(step.takeWatched(jedis, WAIT), "nothing to take")
        }
    }

    @Test
    fun aRenewalDuringTheBlockCostsTheScriptNotAWaitAndTheReplyComesOnce() {
        val runs = AtomicInteger()
        // a lease of 3 s: the service's take waits up to 1 s, which a refused step must not wait out
        OptimusCore.builder().config(CoreConfig.builder().name("$NAME-renewed").build()).redis(TestRedis.url)
            .leaseTime(Duration.ofSeconds(3)).callTimeout(Duration.ofSeconds(20)).build().use { host ->
                val hostLease = host.keys.hostLease("double")
                val double: Block<Int, Int> = host.chain("double") { x: Int ->
                    runs.incrementAndGet()
                    // what the heartbeat's renewal does to the lease while the block runs
                    Jedis(URI(TestRedis.url)).use { it.pexpire(hostLease, 3000) }
                    2 * x
                }.toBlock()
                host.start()
                assertEquals(2, double.process(1), "warm")
                for (i in 2..4) {
                    val started = System.nanoTime()
                    assertEquals(2 * i, double.process(i))
                    val took = Duration.ofNanos(System.nanoTime() - started)
                    assertTrue(took < Duration.ofMillis(900), "the general step stored it at once, not after the take behind it: $took")
                }
                assertEquals(4, runs.get(), "each request processed once")
                assertEquals(0L, raw.llen(host.keys.serviceProcessing("double")), "everything acknowledged")
                assertEquals(0L, raw.llen(host.keys.deadLetters("double")), "no dead letter")
            }
    }

    /** Takes a request, runs [change], and checks that the watched step then stores nothing. */
    private fun refusedAfter(change: () -> Unit) {
        core.connections.open().use { jedis ->
            raw.rpush(input, request)
            val taken = step.takeWatched(jedis, WAIT)!!
            assertTrue(step.isWatched(jedis, taken))
            change()
            assertFalse(step.storeWatched(jedis, RequestOutput(replyKey, reply, isReply = true), WAIT), "Redis refused the step")
            assertNull(step.readTakeBehind(jedis))
            assertFalse(raw.exists(replyKey), "no reply was stored")
            assertEquals(listOf(taken.toList()), raw.lrange(processing, 0, -1).map { it.toList() }, "the request is not acknowledged")
        }
    }

    private companion object {
        const val NAME = "watched-step"
        const val LEASE_MILLIS = 60_000L
        val ME = "me".toByteArray(UTF_8)
        val WAIT = "0.1".toByteArray(UTF_8)
    }
}

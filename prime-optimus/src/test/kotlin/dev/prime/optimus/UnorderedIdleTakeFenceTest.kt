package dev.prime.optimus

import dev.prime.CoreConfig
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration

/**
 * An unordered host's blocking take answered after a survivor reclaimed the host's seat (removed it
 * from the host set while the take waited in Redis, as it does when the host's heartbeat is late)
 * leaves nothing in the host's processing list, which no reclaim looks at any more: the value goes
 * back to the input in Redis, right after the take, so even a host that dies at once strands
 * nothing. The same holds for a service only called, whose host would otherwise wait for its next
 * request by a take written behind its last step.
 */
class UnorderedIdleTakeFenceTest {

    @Test
    fun aTakeAnsweredAfterTheHostLostItsSeatPutsTheValueBackInTheInput() {
        val name = "idle-take-fence"
        Jedis(URI(TestRedis.url)).use { jedis ->
            host(name).use { host ->
                CompetingTopology.declare(host, 0)
                CompetingTopology.core(TestRedis.url, name, null).use { publisher ->
                    val (numbers, _) = CompetingTopology.declare(publisher, 0)
                    publisher.start()
                    host.start()
                    val lengths = reclaimDuringTake(jedis, name, CompetingTopology.SERVICE) { numbers.publish(42) }
                    assertEquals(
                        listOf(1L, 0L), lengths,
                        "[input, processing of a host no longer in the set] within 5 s: the value belongs back at the head of the input",
                    )
                }
            }
        }
    }

    @Test
    fun aCalledServicesNextTakeAnsweredAfterTheHostLostItsSeatPutsTheRequestBackInTheInput() {
        val name = "call-take-fence"
        Jedis(URI(TestRedis.url)).use { jedis ->
            host(name, CALLED).use { host ->
                host.chain(CALLED) { x: Int -> x + 1 }.toBlock()
                host.start()
                OptimusCore.builder()
                    .config(CoreConfig.builder().name(name).build())
                    .redis(TestRedis.url)
                    .hosts(emptyList())
                    .callTimeout(Duration.ofSeconds(2))
                    .build().use { caller ->
                        val echo = caller.chain(CALLED) { x: Int -> x + 1 }.toBlock()
                        caller.start()
                        // two calls: after the second an exclusive host would wait for the next
                        // request by a take written behind its step, not by an idle take
                        assertEquals(2, echo.process(1))
                        assertEquals(3, echo.process(2))
                        val call = Thread { runCatching { echo.process(3) } } // answered late or timed out: either way
                        val lengths = reclaimDuringTake(jedis, name, CALLED) { call.start() }
                        call.join(Duration.ofSeconds(10).toMillis())
                        assertEquals(
                            listOf(1L, 0L), lengths,
                            "[input, processing of a host no longer in the set] within 5 s: the request belongs back at the head of the input",
                        )
                    }
            }
        }
    }

    /**
     * Waits until the only host of [service] blocks in its take, does what a survivor's reclaim does
     * (removes the host from the host set and deletes its seat lease) while the take still waits in
     * Redis, runs [send], then reads the lengths of the input and of the host's processing list
     * together until they are [1, 0] (at most 5,000 reads, 5 s); returns the last lengths read.
     */
    private fun reclaimDuringTake(jedis: Jedis, name: String, service: String, send: () -> Unit): List<Long> {
        val keys = Keys(name)
        val input = keys.serviceInput(service)
        val hosts = keys.serviceHosts(service)
        val instance = jedis.smembers(hosts).single().toString(UTF_8)
        val processing = keys.hostProcessing(service, instance)
        awaitBlockedTake(jedis, "prime-$name")
        val reclaim = jedis.multi()
        reclaim.srem(hosts, instance.toByteArray(UTF_8))
        reclaim.del(keys.hostSeatLease(service, instance))
        reclaim.exec()
        send()
        // both lengths read at once; the host's take and the check behind it may run between two reads
        val deadline = System.nanoTime() + Duration.ofSeconds(5).toNanos()
        var lengths = listOf(0L, 0L)
        for (poll in 0 until 5_000) {
            val read = jedis.multi()
            read.llen(input)
            read.llen(processing)
            lengths = read.exec().map { it as Long }
            if (lengths == listOf(1L, 0L) || System.nanoTime() > deadline) break
            Thread.sleep(1)
        }
        return lengths
    }

    /** A core of topology [name] hosting [service] unordered. */
    private fun host(name: String, service: String = CompetingTopology.SERVICE): OptimusCore = OptimusCore.builder()
        .config(CoreConfig.builder().name(name).build())
        .redis(TestRedis.url)
        .leaseTime(Duration.ofSeconds(30)) // heartbeat every 10 s: it does not re-seat the host during the test
        .hosts(service)
        .hosting(service, Hosting.UNORDERED)
        .build()

    /** Waits (bounded) until a connection named [clientName] is blocked in `BLMOVE`. */
    private fun awaitBlockedTake(jedis: Jedis, clientName: String) {
        val deadline = System.nanoTime() + Duration.ofSeconds(10).toNanos()
        while (true) {
            val blocked = jedis.clientList().lines().any { line ->
                " name=$clientName " in " $line " && "cmd=blmove" in line && Regex("flags=\\S*b").containsMatchIn(line)
            }
            if (blocked) return
            assertTrue(System.nanoTime() < deadline, "no connection of $clientName blocked in BLMOVE within 10 s")
            Thread.sleep(5)
        }
    }

    private companion object {
        const val CALLED = "called"
    }
}

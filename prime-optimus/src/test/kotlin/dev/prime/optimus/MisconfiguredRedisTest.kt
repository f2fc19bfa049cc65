package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.PrimeException
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.params.ParameterizedTest
import org.junit.jupiter.params.provider.ValueSource
import java.time.Duration

/**
 * A `redis://` URL that names a Redis set up in a way Optimus cannot work with: a Redis without
 * `LMOVE`/`BLMOVE` (older than 6.2, or with the commands renamed away). Each runs on a
 * `redis-server` of its own, with the arguments that make it so, stopped at the end.
 */
class MisconfiguredRedisTest {

    /**
     * A Redis that does not know `LMOVE` or `BLMOVE` (older than 6.2, or with them renamed away)
     * fails `start()` at once with a message naming the command and "Redis 6.2 or newer", instead
     * of services retrying "unknown command" forever.
     */
    @ParameterizedTest
    @ValueSource(strings = ["LMOVE", "BLMOVE"])
    fun aRedisWithoutACommandOptimusNeedsFailsTheStartNamingIt(command: String) {
        EmbeddedRedis.builder().arguments("--rename-command", command, "").start().use { redis ->
            core("misconf-no-${command.lowercase()}", redis.uri).use { core ->
                core.chain("twice") { x: Int -> 2 * x }.toBlock()
                val started = System.nanoTime()
                val e = assertThrows(PrimeException::class.java) { core.start() }
                val took = Duration.ofNanos(System.nanoTime() - started)
                assertTrue(took < Duration.ofSeconds(2), "start() failed after $took")
                assertTrue("the command $command" in e.message!! && "Redis 6.2 or newer" in e.message!!, e.message)
            }
        }
    }

    private fun core(name: String, url: String, publishTimeout: Duration = Duration.ofSeconds(2)): OptimusCore =
        OptimusCore.builder().config(CoreConfig.builder().name(name).build()).redis(url).publishTimeout(publishTimeout).build()
}

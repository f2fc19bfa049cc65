package dev.prime.optimus

import dev.prime.CoreConfig
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertInstanceOf
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration
import java.util.concurrent.Callable
import java.util.concurrent.ExecutionException
import java.util.concurrent.Executors
import java.util.concurrent.TimeUnit

/**
 * Reading and clearing dead letters during a Redis outage (a tool, a dashboard) ends within its
 * bound of 10 s with a [RedisUnavailableException], not when the outage ends
 * ([InterruptedDeadLettersTest] checks an interrupted one).
 */
class DeadLettersOutageTest {

    @Test
    fun deadLetterReadsAndClearsGiveUpWithinTheirBoundWhileRedisIsUnreachable() {
        withCoreThroughProxy("dead-letters-outage") { proxy, core ->
            assertEquals(emptyList<DeadLetter>(), core.deadLetters("double"), "before the outage")
            proxy.refuse()
            val pool = Executors.newFixedThreadPool(3)
            try {
                val began = System.nanoTime()
                val asks = listOf(
                    pool.submit(Callable { core.deadLetters("double") }),
                    pool.submit(Callable { core.trimmedDeadLetters("double") }),
                    pool.submit(Callable { core.clearDeadLetters("double") }),
                )
                for (ask in asks) {
                    val failure = assertThrows(ExecutionException::class.java) { ask.get(BOUND.toSeconds() + 20, TimeUnit.SECONDS) }.cause
                    assertInstanceOf(RedisUnavailableException::class.java, failure, "gives up as Redis is unreachable")
                    assertTrue(Regex("dead.letter.*service 'double'").containsMatchIn(failure!!.message!!), "says what: ${failure.message}")
                }
                val took = Duration.ofNanos(System.nanoTime() - began)
                assertTrue(took <= BOUND.plusSeconds(2), "all three gave up within ${BOUND.plusSeconds(2)}: $took")
            } finally {
                pool.shutdownNow()
                proxy.restore()
            }
            assertEquals(0, core.clearDeadLetters("double"), "after the outage")
        }
    }

    /** Runs [test] with a started core that reaches Redis through a [FaultProxy] and hosts chain `double`. */
    private fun withCoreThroughProxy(name: String, test: (FaultProxy, OptimusCore) -> Unit) {
        val config = CoreConfig.builder().name("$name-${System.nanoTime()}").build()
        EmbeddedRedis.start().use { redis ->
            FaultProxy(redis.uri).use { proxy ->
                OptimusCore.builder().config(config).redis(proxy.url).build().use { core ->
                    core.chain("double") { x: Int -> x * 2 }.toBlock()
                    core.start()
                    test(proxy, core)
                }
            }
        }
    }

    private companion object {
        val BOUND: Duration = Duration.ofSeconds(10)
    }
}

package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import java.time.Duration

/**
 * A declaration after `start()` that hosts a service here claims its host lease, or registers a
 * service's input, in Redis: during an outage it waits for Redis, and an interrupt of that wait
 * ends the declaration with a [dev.prime.PrimeException] that says so, the flag kept, never as
 * [dev.prime.CoreClosedException] (the core is open). Once Redis is back, a new declaration works.
 */
class InterruptedDeclarationTest {

    @Test
    fun declarationsAfterStartInterruptedWhileRedisIsUnreachableFailSayingSo() {
        val config = CoreConfig.builder().name("interrupted-declaration-${System.nanoTime()}").build()
        EmbeddedRedis.start().use { redis ->
            FaultProxy(redis.uri).use { proxy ->
                OptimusCore.builder().config(config).redis(proxy.url).build().use { core ->
                    val events = EventBlock<Int>()
                    val numbers = core.source("numbers", events)
                    core.start()
                    proxy.refuse()
                    val lateChain = core.chain("late") { x: Int -> x + 1 }
                    assertInterruptedInOutage("toBlock() after start()", "late") { lateChain.toBlock() }
                    assertInterruptedInOutage("a link after start()", "numbers") { numbers.then(core.chain("linked") { x: Int -> x }) }
                    assertInterruptedInOutage("a timer after start()", "tick") { core.timer("tick", Duration.ofSeconds(1)) }
                    proxy.restore()
                    val again = core.chain("again") { x: Int -> x + 1 }.toBlock()
                    assertEquals(2, again.process(1), "a chain declared once Redis is back works")
                }
            }
        }
    }
}

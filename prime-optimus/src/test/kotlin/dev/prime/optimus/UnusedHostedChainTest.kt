package dev.prime.optimus

import dev.prime.Block
import dev.prime.CoreConfig
import dev.prime.PrimeException
import dev.prime.conformance.CapturedStderr
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.params.ParameterizedTest
import org.junit.jupiter.params.provider.ValueSource
import java.time.Duration

/**
 * A chain's service runs once the chain is used in the process that hosts it: a process told to
 * host a chain it never used by `start()` gets one WARN naming it (calls from other processes would
 * wait out their timeout), and a process that used the chain gets none. On a plain Redis and
 * through the slow link of the kit's slow-Redis variant.
 */
class UnusedHostedChainTest {

    @ParameterizedTest
    @ValueSource(booleans = [false, true])
    fun aHostedChainThatNothingUsedIsNamedInOneWarningAndCallsToItTimeOut(slow: Boolean) {
        val topology = "unused-hosted" + if (slow) "-slow" else ""
        val url = urlOf(slow)
        CapturedStderr().use { err ->
            host(topology, url).use { host ->
                host.chain("square", Block<Int, Int> { it * it })
                host.chain("unused-twice", Block<Int, Int> { it * 2 }) // not named in hosts(): no warning
                host.start()
                caller(topology, url).use { caller ->
                    val square = caller.chain("square", Block<Int, Int> { it * it }).toBlock()
                    caller.chain("unused-twice", Block<Int, Int> { it * 2 })
                    caller.start()
                    val failure = assertThrows(PrimeException::class.java) { square.process(3) }
                    assertTrue("did not reply within" in failure.message!!, failure.message)
                }
            }
            val warnings = err.lines().filter { " WARN " in it && "core '$topology'" in it && "by start()" in it }
            assertEquals(1, warnings.size, "warnings: $warnings")
            assertTrue("is told to host [square], but no chain of this process has used it" in warnings.single(), warnings.single())
        }
    }

    @ParameterizedTest
    @ValueSource(booleans = [false, true])
    fun aHostedChainUsedByStartGetsNoWarningAndAnswersCalls(slow: Boolean) {
        val topology = "used-hosted" + if (slow) "-slow" else ""
        val url = urlOf(slow)
        CapturedStderr().use { err ->
            host(topology, url).use { host ->
                host.chain("square", Block<Int, Int> { it * it }).toBlock()
                host.start()
                caller(topology, url).use { caller ->
                    val square = caller.chain("square", Block<Int, Int> { it * it }).toBlock()
                    caller.start()
                    assertEquals(9, square.process(3))
                }
            }
            assertEquals(emptyList<String>(), err.lines().filter { " WARN " in it && "by start()" in it })
        }
    }

    private fun urlOf(slow: Boolean): String = if (slow) FaultProxy.slowLinkTo(TestRedis.url) else TestRedis.url

    private fun host(topology: String, url: String): OptimusCore =
        OptimusCore.builder().config(CoreConfig.builder().name(topology).build()).redis(url).hosts("square").build()

    private fun caller(topology: String, url: String): OptimusCore =
        OptimusCore.builder().config(CoreConfig.builder().name(topology).build()).redis(url)
            .hosts(emptyList()).callTimeout(Duration.ofSeconds(1)).build()
}

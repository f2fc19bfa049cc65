package dev.prime.optimus

import dev.prime.Block
import dev.prime.CoreConfig
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicReference

/**
 * A service on the path of a call ([CallPaths]) is refused as called from inside itself only
 * while it still waits for that call: once its call gave up (its call timeout), it is free to take
 * a call back from the block that still runs its request.
 */
class GivenUpCallPathTest {

    @Test
    fun aCallBackToACallerThatGaveUpIsServed() {
        val config = CoreConfig.builder().name("given-up-path-${System.nanoTime()}").build()
        val callerGaveUp = CountDownLatch(1)
        val calledBack = CountDownLatch(1)
        val callBack = AtomicReference<Any?>()
        // the user calls through a core of the same topology that hosts nothing, with the default call timeout
        OptimusCore.builder().config(config).redis(TestRedis.url).hosts(emptyList()).build().use { user ->
            OptimusCore.builder().config(config).redis(TestRedis.url).callTimeout(CALL_TIMEOUT).build().use { core ->
                val callerBlock = AtomicReference<Block<Int, Int>>()
                val slow = core.chain("slow") { x: Int ->
                    // runs the request of 'caller', whose call gives up meanwhile
                    assertTrue(callerGaveUp.await(PATIENCE_SECONDS, TimeUnit.SECONDS), "the caller's call gave up")
                    try {
                        callBack.set(callerBlock.get().process(0))
                    } catch (e: Throwable) {
                        callBack.set(e)
                    } finally {
                        calledBack.countDown()
                    }
                    x
                }.toBlock()
                callerBlock.set(
                    core.chain("caller") { x: Int ->
                        if (x == 0) {
                            -1
                        } else {
                            try {
                                slow.process(x)
                            } catch (_: Exception) {
                                callerGaveUp.countDown()
                                -2
                            }
                        }
                    }.toBlock(),
                )
                user.chain("slow") { x: Int -> x }
                val userCall = user.chain("caller") { x: Int -> x }.toBlock()
                core.start()
                user.start()
                assertEquals(-2, userCall.process(1), "the caller's call to 'slow' gave up by its timeout")
                assertTrue(calledBack.await(PATIENCE_SECONDS, TimeUnit.SECONDS), "the call back ended")
                val result = callBack.get()
                assertNull((result as? Throwable)?.let { "the call back failed: $it" })
                assertEquals(-1, result, "the caller, free again, served the call back")
            }
        }
    }

    private companion object {
        val CALL_TIMEOUT: Duration = Duration.ofSeconds(2)

        /** Far above the call timeout: a wait that ends within it ended as it should. */
        const val PATIENCE_SECONDS = 30L
    }
}

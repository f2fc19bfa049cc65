package dev.prime.optimus

import dev.prime.ChainFailedException
import dev.prime.CoreConfig
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/**
 * Two cores of one topology (same name, same Redis) stand for two processes: a service hosted
 * by one, called from the other.
 */
class RemoteFailureTest {

    @Test
    fun callerInAnotherProcessGetsTheServiceNameAndTheFailure() {
        val config = CoreConfig.builder().name("remote-failure-topology").build()
        fun declare(core: OptimusCore) =
            core.chain("parse") { s: String -> Integer.parseInt(s) }

        OptimusCore.builder().config(config).redis(TestRedis.url).hosts("parse").build().use { host ->
            declare(host).toBlock()
            host.start()
            OptimusCore.builder().config(config).redis(TestRedis.url).hosts().build().use { caller ->
                val parse = declare(caller)
                caller.start()
                assertEquals(setOf<String>(), caller.serviceNames(), "the caller hosts nothing")
                val block = parse.toBlock()
                assertEquals(12, block.process("12"))
                val e = assertThrows(ChainFailedException::class.java) { block.process("twelve") }
                assertEquals("parse", e.chainName())
                assertTrue(e.cause is RemoteFailureException, e.cause.toString())
                assertTrue(e.cause!!.message!!.contains("NumberFormatException"), e.cause!!.message)
                assertEquals(13, block.process("13"), "the service goes on")
            }
        }
    }

    @Test
    fun anErrorInAServiceOfAnotherProcessReachesTheCallerAsRemoteFailureAndTheServiceGoesOn() {
        val config = CoreConfig.builder().name("remote-error-topology").build()
        fun declare(core: OptimusCore) =
            core.chain("check") { x: Int -> if (x < 0) throw AssertionError("negative: $x") else x }

        OptimusCore.builder().config(config).redis(TestRedis.url).hosts("check").build().use { host ->
            declare(host).toBlock()
            host.start()
            OptimusCore.builder().config(config).redis(TestRedis.url).hosts().build().use { caller ->
                val check = declare(caller)
                caller.start()
                val block = check.toBlock()
                val e = assertThrows(ChainFailedException::class.java) { block.process(-1) }
                assertEquals("check", e.chainName())
                assertTrue(e.cause is RemoteFailureException, e.cause.toString())
                assertTrue(e.cause!!.message!!.contains("AssertionError"), e.cause!!.message)
                assertEquals(2, block.process(2), "the service survived the error")
            }
        }
    }

    @Test
    fun hostingAServiceTheTopologyDoesNotDeclareIsRefusedAtStart() {
        OptimusCore.builder().redis(TestRedis.url).hosts("typo").build().use { core ->
            core.chain("real") { x: Int -> x }.toBlock()
            val e = assertThrows(IllegalArgumentException::class.java) { core.start() }
            assertTrue(e.message!!.contains("typo") && e.message!!.contains("real"), e.message)
        }
    }
}

package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.conformance.CapturedStderr
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertDoesNotThrow
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.function.Executable
import java.time.Duration
import java.util.UUID

/**
 * The builder refuses a setting out of its range at once, with a message naming the setting and
 * the value given; `start()` refuses `hosts(...)` names the topology does not declare and hosting
 * modes for services that are not chains'.
 */
class OptimusBuilderInputTest {

    private fun refused(setting: String, value: String, set: OptimusCore.Builder.() -> Unit) {
        val e = assertThrows(IllegalArgumentException::class.java) { OptimusCore.builder().set() }
        assertTrue(setting in e.message!! && value in e.message!!, "the message names '$setting' and '$value': ${e.message}")
    }

    @Test
    fun settingsOutOfRangeAreRefusedNamingTheSettingAndTheValue() {
        refused("retries", "-1") { retries(-1) }
        refused("call timeout", "PT-1S") { callTimeout(Duration.ofSeconds(-1)) }
        refused("lease time", "PT0.299S") { leaseTime(Duration.ofMillis(299)) }
        refused("lease time", "PT24H0.001S") { leaseTime(Duration.ofHours(24).plusMillis(1)) }
        refused("lease time", "was PT${Long.MAX_VALUE / 3600}H") { leaseTime(Duration.ofSeconds(Long.MAX_VALUE)) }
        refused("queue limit", "was 0") { queueLimit(0) }
        refused("queue limit of service 'slow'", "was -3") { queueLimit("slow", -3) }
        refused("publish timeout", "PT-0.001S") { publishTimeout(Duration.ofMillis(-1)) }
        refused("max value bytes", "was 0") { maxValueBytes(0) }
        refused("dead-letter limit", "was 0") { deadLetterLimit(0) }
        refused("replica acks", "-1") { replicaAcks(-1) }
        refused("hosting(...)", "named") { hosting(" ", Hosting.ORDERED) }
    }

    @Test
    fun theBoundsThemselvesAreAccepted() {
        val builder = OptimusCore.builder()
        val bounds = listOf<Executable>(
            Executable { builder.retries(0) },
            Executable { builder.callTimeout(Duration.ZERO) },
            Executable { builder.leaseTime(Duration.ofMillis(300)) },
            Executable { builder.leaseTime(Duration.ofHours(24)) },
            Executable { builder.queueLimit(1) },
            Executable { builder.queueLimit("slow", 1) },
            Executable { builder.publishTimeout(Duration.ZERO) },
            Executable { builder.maxValueBytes(1) },
            Executable { builder.deadLetterLimit(1) },
            Executable { builder.replicaAcks(0) },
        )
        bounds.forEach(::assertDoesNotThrow)
    }

    /**
     * The call timeout takes any duration that is not negative, so the longest a [Duration] holds
     * (a program's "as long as it takes") builds a core whose calls are answered like any other.
     */
    @Test
    fun theLongestCallTimeoutWorksLikeAnyOther() {
        OptimusCore.builder().config(config()).redis(TestRedis.url)
            .callTimeout(Duration.ofSeconds(Long.MAX_VALUE, 999_999_999)).build().use { core ->
                val triple = core.chain("triple") { x: Int -> 3 * x }.toBlock()
                core.start()
                assertEquals(6, triple.process(2))
            }
    }

    /** The longest lease the builder takes (24 h) builds a core whose services answer. */
    @Test
    fun theLongestLeaseWorksLikeAnyOther() {
        OptimusCore.builder().config(config()).redis(TestRedis.url).leaseTime(Duration.ofHours(24)).build().use { core ->
            val triple = core.chain("triple") { x: Int -> 3 * x }.toBlock()
            core.start()
            assertEquals(6, triple.process(2))
        }
    }

    @Test
    fun startWarnsOfAQueueLimitForAServiceItsChainsDoNotHave() {
        val lines = CapturedStderr().use { err ->
            OptimusCore.builder().config(config()).redis(TestRedis.url)
                .queueLimit("dubble", 5).queueLimit("double", 7).build().use { core ->
                    core.source("numbers", EventBlock<Int>()).then(core.chain("double") { x: Int -> 2 * x })
                    core.start()
                }
            err.lines().filter { "queue limits" in it }
        }
        assertEquals(1, lines.size, "one line: $lines")
        assertTrue(" WARN " in lines[0] && "[dubble]" in lines[0], "names the unknown one only: ${lines[0]}")
    }

    @Test
    fun startRefusesToHostAServiceTheTopologyDoesNotDeclare() {
        OptimusCore.builder().config(config()).redis(TestRedis.url).hosts("double", "tripple").build().use { core ->
            core.chain("double") { x: Int -> 2 * x }
            val e = assertThrows(IllegalArgumentException::class.java) { core.start() }
            assertTrue("[tripple]" in e.message!! && "does not declare" in e.message!! && "[double]" in e.message!!, e.message)
            assertEquals(setOf<String>(), core.serviceNames(), "the refused start runs nothing here, and says so")
        }
    }

    @Test
    fun startRefusesAHostingModeForACombinatorOrATimer() {
        for (service in listOf("combineLatest(a|b)", "tick")) {
            OptimusCore.builder().config(config()).redis(TestRedis.url).hosting(service, Hosting.UNORDERED).build().use { core ->
                core.combineLatest(core.source("a", EventBlock<Int>()), core.source("b", EventBlock<Int>()))
                core.timer("tick", Duration.ofSeconds(1))
                assertTrue(service in core.topology().services(), "${core.topology().services()}")
                val e = assertThrows(IllegalArgumentException::class.java) { core.start() }
                assertTrue("[$service]" in e.message!! && "Hosting.EXCLUSIVE" in e.message!!, e.message)
            }
        }
    }

    private fun config(): CoreConfig = CoreConfig.builder().name("builder-input-" + UUID.randomUUID()).build()
}

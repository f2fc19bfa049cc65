package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.util.Optional
import java.util.UUID

/** `publishAll` refuses a null value and a source of another core with `IllegalArgumentException`, publishing nothing. */
class PublishAllTest {

    @Test
    fun aNullAmongTheValuesIsRefusedAndNothingIsPublished() {
        TestRedis.core(named()).use { core ->
            val numbers = core.source("numbers", EventBlock<Int?>())
            val reader = numbers.reader()
            core.start()
            val refused = assertThrows(IllegalArgumentException::class.java) { core.publishAll(numbers, listOf(1, null, 3)) }
            assertTrue("null" in refused.message!!, refused.message)
            assertEquals(Optional.empty<Int>(), reader.poll(), "the value before the null was not published")
            core.publishAll(numbers, listOf(4))
            assertEquals(listOf(4), reader.drain())
        }
    }

    @Test
    fun aSourceOfAnotherCoreIsRefused() {
        TestRedis.core(named()).use { mine ->
            TestRedis.core(named()).use { other ->
                val foreign = other.source("numbers", EventBlock<Int>())
                mine.start()
                val refused = assertThrows(IllegalArgumentException::class.java) { mine.publishAll(foreign, listOf(1)) }
                assertTrue("is not a source of" in refused.message!!, refused.message)
            }
        }
    }

    private fun named(): CoreConfig = CoreConfig.builder().name("publish-all-" + UUID.randomUUID()).build()
}

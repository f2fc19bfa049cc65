package dev.prime.optimus

import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration

/** A publish while Redis is unreachable gives up at the publish timeout with `RedisUnavailableException`. */
class PublishOutageTest {

    @Test
    fun aPublishDuringAnOutageHonoursThePublishTimeout() {
        EmbeddedRedis.start().use { redis ->
            OptimusCore.builder().redis(redis.uri).publishTimeout(Duration.ofSeconds(1)).build().use { core ->
                val events = EventBlock<Int>()
                core.source("numbers", events).reader()
                core.start()
                events.publish(1)
                redis.close()
                val started = System.nanoTime()
                val refused = assertThrows(RedisUnavailableException::class.java) { events.publish(2) }
                val waited = Duration.ofNanos(System.nanoTime() - started)
                assertTrue(waited <= Duration.ofSeconds(2), "gave up after $waited")
                assertTrue("publish to source 'numbers'" in refused.message!!, refused.message)
            }
        }
    }
}

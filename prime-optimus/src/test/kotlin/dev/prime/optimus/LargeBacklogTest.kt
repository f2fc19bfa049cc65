package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.util.UUID
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicInteger

/**
 * A backlog of large values is taken in batches bounded by bytes (8 MiB by default), not only by
 * count: with 40 values of 2 MiB waiting, a step never holds more than 5 of them.
 */
class LargeBacklogTest {

    @Test
    fun aBacklogOfLargeValuesIsProcessedInBatchesBoundedByBytes() {
        val config = CoreConfig.builder().name("blobs-" + UUID.randomUUID()).sourceRetention(2).build()
        OptimusCore.builder().config(config).redis(TestRedis.url).hosts(emptyList()).build().use { publisher ->
            val blobs = declare(publisher) { }
            publisher.start()
            publisher.publishAll(blobs, List(COUNT) { i -> ByteArray(SIZE) { i.toByte() } })

            val done = CountDownLatch(COUNT)
            val largestBatch = AtomicInteger()
            val seen = AtomicInteger()
            Jedis(URI(TestRedis.url)).use { probe ->
                OptimusCore.builder().config(config).redis(TestRedis.url).hosts("measure").build().use { worker ->
                    val processing = worker.keys.serviceProcessing("measure")
                    declare(worker) { blob ->
                        largestBatch.accumulateAndGet(probe.llen(processing).toInt(), ::maxOf)
                        if (blob.size == SIZE && blob[0] == seen.get().toByte()) seen.incrementAndGet()
                        done.countDown()
                    }
                    worker.start()
                    assertTrue(done.await(PATIENCE_S, TimeUnit.SECONDS), "${done.count} of $COUNT values not processed")
                }
            }
            assertEquals(COUNT, seen.get(), "every value, whole and in order")
            assertTrue(largestBatch.get() in 1..5, "a step held ${largestBatch.get()} values of 2 MiB")
        }
    }

    private fun declare(core: OptimusCore, measure: (ByteArray) -> Unit): dev.prime.Source<ByteArray> {
        val blobs = core.source("blobs", EventBlock<ByteArray>())
        blobs.then(core.chain("measure") { blob: ByteArray -> measure(blob); 0 })
        return blobs
    }

    private companion object {
        const val COUNT = 40
        const val SIZE = 2 * 1024 * 1024
        const val PATIENCE_S = 60L
    }
}

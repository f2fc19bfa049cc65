package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI
import java.nio.ByteBuffer
import java.time.Duration
import java.util.Optional
import java.util.UUID
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * Frames in one process: values that are ready together travel in one Redis entry, a lone value
 * is sent at once (nothing waits to fill a frame), values of mixed sizes are split over frames by
 * the byte bound, and a reader's retention is counted in values.
 */
class FramedDeliveryTest {

    private fun OptimusCore.valueWithId(value: Int, id: Long) = Envelope.withId(valueEnvelope(value), id)

    private fun frameOf(envelopes: List<ByteArray>) = Frame.pack(envelopes, Frame.DEFAULT_BYTES, always = true).single()

    private fun config(retention: Int = 1000) =
        CoreConfig.builder().name("frames-" + UUID.randomUUID()).sourceRetention(retention).build()

    @Test
    fun aBurstTravelsInFramesAndALoneValueIsSentAtOnce() {
        val lone = CountDownLatch(1)
        OptimusCore.builder().config(config(4000)).redis(TestRedis.url).build().use { core ->
            val events = EventBlock<Int>()
            val numbers = core.source("numbers", events)
            val output = core.link(numbers, core.chain("mark") { x: Int -> if (x == LONE) lone.countDown(); x + 1 }).reader()
            core.start()
            core.publishAll(numbers, (0 until 1000).toList())
            val burst = (0 until 1000).map { output.take(PATIENCE).orElseThrow() }
            assertEquals((1..1000).toList(), burst)
            Jedis(URI(TestRedis.url)).use { raw ->
                val log = raw.lrange(core.keys.sourceLog("numbers"), 0, -1)
                // 1000 values in 4 entries (at most 256 values each) instead of 1000
                assertEquals(listOf(256, 256, 256, 232), log.map(Frame::count))
                val numbered = raw.lrange(core.keys.sourceLog("numbers") + ":numbers".toByteArray(), 0, -1).map(Frame::numbered)
                assertEquals(listOf(1L to 256, 257L to 256, 513L to 256, 769L to 232), numbered, "each frame numbered in its source")
                assertTrue(log.all { Frame.isFrame(it) && ByteBuffer.wrap(it, 2, 8).long == 0L }, "frames stored as published")
            }

            // nothing else is published after it: a batcher that waited to fill a frame would never send it
            val sent = System.nanoTime()
            events.publish(LONE)
            assertTrue(lone.await(PATIENCE.seconds, TimeUnit.SECONDS), "the lone value did not reach the service")
            val reached = Duration.ofNanos(System.nanoTime() - sent)
            assertEquals(Optional.of(LONE + 1), output.take(PATIENCE))
            assertTrue(reached < Duration.ofSeconds(2), "the lone value reached the service after $reached")
            Jedis(URI(TestRedis.url)).use { raw ->
                assertEquals(1, Frame.count(raw.lindex(core.keys.sourceLog("numbers"), -1)), "a frame of just that value")
            }
            assertEquals(Optional.empty<Int>(), output.poll())
        }
    }

    @Test
    fun anUndecodableEnvelopeInAFrameIsDeadLetteredAloneAndTheFrameAroundItIsHandled() {
        OptimusCore.builder().config(config()).redis(TestRedis.url).build().use { core ->
            val numbers = core.source("numbers", EventBlock<Int>())
            val output = core.link(numbers, core.chain("mark") { x: Int -> x + 1 }).reader()
            core.start()
            val values = listOf(
                core.valueWithId(10, 101L),
                GARBAGE,
                core.valueWithId(20, 102L),
                core.valueWithId(30, 103L),
            )
            val frame = frameOf(values)
            Jedis(URI(TestRedis.url)).use { raw -> raw.rpush(core.keys.serviceInput("mark"), frame) }
            assertEquals(listOf(11, 21, 31), List(3) { output.take(PATIENCE).orElseThrow() }, "the frame's other values, in order")
            val dead = core.deadLetters("mark").single()
            assertTrue(dead.reason.startsWith("undecodable envelope"), dead.reason)
            assertEquals(GARBAGE.toList(), dead.bytes().toList(), "the dead letter holds that envelope, not the frame")
            assertEquals(Optional.empty<Int>(), output.poll())
        }
    }

    @Test
    fun aReaderHandsOutAFramesValuesSkippingBadAndRepeatedOnesAndAcknowledgesItOnce() {
        OptimusCore.builder().config(config()).redis(TestRedis.url).build().use { core ->
            val reader = core.source("numbers", EventBlock<Int>()).reader() as OptimusReader<Int>
            core.start()
            val values = listOf(
                core.valueWithId(1, 201L),
                GARBAGE,
                core.valueWithId(2, 202L),
                Envelope.value(203L, null), // a null value: a reader hands out none
                core.valueWithId(1, 201L), // a repeated id
                core.valueWithId(3, 204L),
                core.valueWithId(2, 202L), // the frame ends with a repeated id
            )
            val frame = frameOf(values)
            Jedis(URI(TestRedis.url)).use { raw ->
                raw.rpush(reader.list, frame)
                raw.rpush(reader.list, core.valueWithId(4, 205L)) // a single value after it
                assertEquals(listOf(1, 2, 3, 4), List(4) { reader.take(PATIENCE).orElseThrow() }, "the good values, once each, in order")
                assertEquals(Optional.empty<Int>(), reader.poll())
                // the poll's step acknowledged both entries: the frame once, though its last envelope was skipped
                assertEquals(0L, raw.llen(core.keys.processingOf(reader.list)), "entries left in the reader's processing list")
            }
        }
    }

    @Test
    fun valuesOfMixedSizesAreSplitOverFramesAndAllArriveInOrder() {
        val sizes = listOf(1, 100, 10_000, 70_000, 300, 0, 40_000)
        val values = (0 until 300).map { i -> ByteArray(sizes[i % sizes.size]) { (i + it).toByte() } }
        OptimusCore.builder().config(config(1000)).redis(TestRedis.url).frameBytes(FRAME_BYTES).build().use { core ->
            val numbers = core.source("blobs", EventBlock<ByteArray>())
            val output = core.link(numbers, core.chain("copy") { x: ByteArray -> x.copyOf() }).reader()
            core.start()
            core.publishAll(numbers, values)
            val received = values.indices.map { output.take(PATIENCE).orElseThrow() }
            assertEquals(values.map { it.toList() }, received.map { it.toList() })
            Jedis(URI(TestRedis.url)).use { raw ->
                val log = raw.lrange(core.keys.sourceLog("blobs"), 0, -1)
                assertEquals(300, log.sumOf(Frame::count))
                assertTrue(log.size > 10, "split by the byte bound: ${log.size} entries")
                for (entry in log) assertTrue(entry.size <= FRAME_BYTES || Frame.count(entry) == 1, "${entry.size} bytes")
            }
        }
    }

    @Test
    fun framesStayWithinTheEntrySizeLimitOfASmallMaxValueBytes() {
        // 50 values of 3,000 bytes: 150 KB together, over the entry size limit that maxValueBytes(4096) sets
        val values = (0 until 50).map { i -> ByteArray(3000) { (i * it).toByte() } }
        OptimusCore.builder().config(config(1000)).redis(TestRedis.url).maxValueBytes(4096).build().use { core ->
            val numbers = core.source("blobs", EventBlock<ByteArray>())
            val output = core.link(numbers, core.chain("copy") { x: ByteArray -> x.copyOf() }).reader()
            core.start()
            core.publishAll(numbers, values)
            val received = values.indices.map { output.take(PATIENCE).orElseThrow() }
            assertEquals(values.map { it.toList() }, received.map { it.toList() })
            assertEquals(emptyList<DeadLetter>(), core.deadLetters("copy"), "no frame was too large for its consumer")
        }
    }

    @Test
    fun aReaderKeepsItsRetentionInValuesAndCountsWhatItMissed() {
        OptimusCore.builder().config(config(100)).redis(TestRedis.url).build().use { core ->
            val numbers = core.source("numbers", EventBlock<Int>())
            val reader = numbers.reader()
            core.start()
            repeat(10) { batch -> core.publishAll(numbers, (batch * 50 until batch * 50 + 50).toList()) }
            // 500 values in frames of 50: the 8 oldest frames are trimmed whole, the newest 100 values stay
            assertEquals(400L, reader.missed())
            assertEquals((400 until 500).toList(), reader.drain())
            Jedis(URI(TestRedis.url)).use { raw -> assertEquals(100L, TestRedis.values(raw, core.keys.sourceLog("numbers"))) }
        }
    }

    @Test
    fun aReaderThatTookPartOfItsListIsTrimmedByTheValuesItStillHolds() {
        OptimusCore.builder().config(config(100)).redis(TestRedis.url).build().use { core ->
            val numbers = core.source("numbers", EventBlock<Int>())
            val reader = numbers.reader()
            core.start()
            repeat(2) { batch -> core.publishAll(numbers, (batch * 50 until batch * 50 + 50).toList()) }
            assertEquals(0, reader.take(PATIENCE).orElseThrow()) // takes both frames into its processing list
            // the log numbers 3 to 5 frames while the reader's list holds only what came after its take
            (2 until 5).forEach { batch -> core.publishAll(numbers, (batch * 50 until batch * 50 + 50).toList()) }
            assertEquals(50L, reader.missed(), "values 100-149 fell out of the retention of 100")
            assertEquals((1 until 100).toList() + (150 until 250).toList(), reader.drain())
            Jedis(URI(TestRedis.url)).use { raw ->
                assertEquals(100L, TestRedis.values(raw, core.keys.sourceLog("numbers")))
                assertEquals(2L, raw.llen(core.keys.sourceLog("numbers") + ":numbers".toByteArray()), "one number per log entry")
            }
        }
    }

    @Test
    fun entriesWhoseNumbersWereLostAreTrimmedOnceTheNumberedOnesHoldTheRetention() {
        OptimusCore.builder().config(config(100)).redis(TestRedis.url).build().use { core ->
            val numbers = core.source("numbers", EventBlock<Int>())
            val reader = numbers.reader()
            core.start()
            val log = core.keys.sourceLog("numbers")
            val logNumbers = log + ":numbers".toByteArray()
            Jedis(URI(TestRedis.url)).use { raw ->
                repeat(2) { batch -> core.publishAll(numbers, (batch * 50 until batch * 50 + 50).toList()) }
                raw.del(logNumbers) // as if Redis lost them: two entries without numbers in the log and the reader
                core.publishAll(numbers, (100 until 150).toList())
                assertEquals(150L, TestRedis.values(raw, log), "kept while the numbered entries hold less than the retention")
                (3 until 5).forEach { batch -> core.publishAll(numbers, (batch * 50 until batch * 50 + 50).toList()) }
                assertEquals(100L, TestRedis.values(raw, log))
                assertEquals(listOf(151L to 50, 201L to 50), raw.lrange(logNumbers, 0, -1).map(Frame::numbered))
            }
            assertEquals(150L, reader.missed())
            assertEquals((150 until 250).toList(), reader.drain())
        }
    }

    @Test
    fun requestsOfManyCallersAreNeverCountedAgainstAQueue() {
        OptimusCore.builder().config(config()).redis(TestRedis.url).build().use { core ->
            val chain = core.link(core.chain("first") { x: Int -> x + 1 }, core.chain("second") { x: Int -> x * 2 })
            val block = chain.toBlock()
            core.start()
            val pool = java.util.concurrent.Executors.newFixedThreadPool(8)
            try {
                val results = (0 until 8).map { t -> pool.submit<List<Int>> { (0 until 50).map { block.process(t * 100 + it) } } }
                results.forEachIndexed { t, result ->
                    assertEquals((0 until 50).map { (t * 100 + it + 1) * 2 }, result.get(PATIENCE.seconds, TimeUnit.SECONDS))
                }
            } finally {
                pool.shutdownNow()
            }
            Jedis(URI(TestRedis.url)).use { raw ->
                for (service in listOf("first", "second")) {
                    assertEquals(null, raw.get(core.keys.queuedOf(core.keys.serviceInput(service))), "no queue count for '$service'")
                }
            }
        }
    }

    @Test
    fun queueDepthAndQueueLimitCountValuesInFrames() {
        val inside = CountDownLatch(1)
        val release = CountDownLatch(1)
        val config = CoreConfig.builder().name("frames-" + UUID.randomUUID()).metrics(true).publishTimeout(Duration.ofMillis(200)).build()
        OptimusCore.builder().config(config).redis(TestRedis.url).queueLimit("stuck", 300).build().use { core ->
            val numbers = core.source("numbers", EventBlock<Int>())
            val output = core.link(numbers, core.chain("stuck") { x: Int -> inside.countDown(); release.await(); x }).reader()
            core.start()
            core.publishAll(numbers, (0 until 10).toList()) // one frame, taken whole by the service
            assertTrue(inside.await(PATIENCE.seconds, TimeUnit.SECONDS))
            core.publishAll(numbers, (10 until 300).toList())
            assertEquals(300L, core.metrics().service("stuck").queueDepth(), "10 in progress (one frame) and 290 waiting")
            // 290 values wait in 2 entries: a count of entries would take many more
            val full = org.junit.jupiter.api.Assertions.assertThrows(QueueFullException::class.java) {
                core.publishAll(numbers, (300 until 311).toList())
            }
            assertTrue("holds 290 values" in full.message!!, full.message)
            core.publishAll(numbers, (300 until 310).toList())
            release.countDown()
            assertEquals((0 until 310).toList(), (0 until 310).map { output.take(PATIENCE).orElseThrow() })
        }
    }

    private companion object {
        const val LONE = 7777

        /** 'P', then an envelope kind that does not exist. */
        val GARBAGE = byteArrayOf(0x50, 9, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10)
        const val FRAME_BYTES = 64 * 1024
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.util.UUID
import java.util.concurrent.CopyOnWriteArrayList
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * A service's input is a queue, not a retention window: with the process that hosts it down,
 * more values than the source retains are published, and every one of them is processed once the
 * host comes up. A plain reader of the same source is trimmed to the retention and told how much
 * it missed.
 */
class ServiceQueueTest {

    @Test
    fun aServiceWhoseHostIsDownLosesNothingBeyondTheRetention() {
        val config = CoreConfig.builder().name("queue-" + UUID.randomUUID()).sourceRetention(RETENTION).build()
        val seen = CopyOnWriteArrayList<Int>()
        val all = CountDownLatch(VALUES)
        OptimusCore.builder().config(config).redis(TestRedis.url).hosts(emptyList()).build().use { publisher ->
            val events = EventBlock<Int>()
            declare(publisher, events) { }
            val plain = publisher.sources().numbers.reader()
            publisher.start()
            (0 until VALUES).forEach(events::publish) // nobody hosts "record" now

            OptimusCore.builder().config(config).redis(TestRedis.url).hosts("record").build().use { worker ->
                declare(worker, EventBlock()) { x ->
                    seen += x
                    all.countDown()
                }
                worker.start()
                all.await(PATIENCE_S, TimeUnit.SECONDS)
                assertEquals((0 until VALUES).toList(), seen.toList(), "the service lost values to the retention")
            }
            assertEquals((VALUES - RETENTION).toLong(), plain.missed(), "a plain reader keeps the retention only")
            assertEquals((VALUES - RETENTION until VALUES).toList(), plain.drain())
            assertTrue(publisher.deadLetters("record").isEmpty())
        }
    }

    private class Declared(val numbers: dev.prime.Source<Int>)

    private var declared: Declared? = null

    private fun OptimusCore.sources(): Declared = declared!!

    private fun declare(core: OptimusCore, events: EventBlock<Int>, record: (Int) -> Unit) {
        val numbers = core.source("numbers", events)
        numbers.then(core.chain("record") { x: Int -> record(x); x })
        if (declared == null) declared = Declared(numbers)
    }

    private companion object {
        const val RETENTION = 16
        const val VALUES = 200
        const val PATIENCE_S = 20L
    }
}

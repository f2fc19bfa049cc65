package dev.prime.kotlin

import dev.prime.CoreClosedException
import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.Reader
import dev.prime.Source
import dev.prime.ValueCodec
import dev.prime.conformance.CapturedStderr
import kotlinx.coroutines.CompletableDeferred
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.TimeoutCancellationException
import kotlinx.coroutines.async
import kotlinx.coroutines.awaitCancellation
import kotlinx.coroutines.channels.Channel
import kotlinx.coroutines.flow.flow
import kotlinx.coroutines.flow.first
import kotlinx.coroutines.flow.flowOf
import kotlinx.coroutines.flow.map
import kotlinx.coroutines.flow.onEach
import kotlinx.coroutines.flow.take
import kotlinx.coroutines.flow.toList
import kotlinx.coroutines.runBlocking
import kotlinx.coroutines.withTimeout
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertInstanceOf
import org.junit.jupiter.api.Assertions.assertNotEquals
import org.junit.jupiter.api.Assertions.assertSame
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.assertThrows
import java.nio.ByteBuffer
import java.time.Duration
import java.util.Optional
import java.util.concurrent.ArrayBlockingQueue
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicBoolean
import java.util.concurrent.atomic.AtomicInteger
import java.util.concurrent.atomic.AtomicReference

/** Sources as flows and flows as sources, on one media. */
internal abstract class FlowKit(private val media: Media) {

    @Test
    fun `a source's flow emits every value in order and completes normally when the core closes`() = runBlocking {
        val core = media.newCore()
        val events = EventBlock<Int>()
        val source = core.source("numbers", events)
        core.start()
        val seen = Channel<Int>(Channel.UNLIMITED)
        val all = async(Dispatchers.IO) { source.asFlow().onEach { seen.send(it) }.toList() }
        (1..5).forEach(events::publish)
        repeat(5) { assertEquals(it + 1, withTimeout(WAIT_MILLIS) { seen.receive() }) }
        core.close()
        assertEquals((1..5).toList(), withTimeout(WAIT_MILLIS) { all.await() }) // not CoreClosedException
        assertEquals(emptyList<Int>(), source.asFlow().toList(), "a closed core's source flows nothing")
    }

    @Test
    fun `cancelling a source's collector ends its blocked take promptly, closes its reader, and the source flows again`() = runBlocking {
        media.newCore().use { core ->
            val events = EventBlock<Int>()
            val source = core.source("numbers", events)
            core.start()
            val seen = Channel<Int>(Channel.UNLIMITED)
            val collector = async(Dispatchers.IO) { source.asFlow().collect { seen.send(it) } }
            events.publish(1)
            assertEquals(1, withTimeout(WAIT_MILLIS) { seen.receive() })
            media.readersKept(core, "numbers")?.let { assertEquals(1L, it, "readers kept while the flow is collected") }
            val began = System.nanoTime()
            collector.cancel() // its reader waits in take() for a second value
            withTimeout(WAIT_MILLIS) { collector.join() }
            val millis = (System.nanoTime() - began) / 1_000_000
            assertTrue(millis < PROMPT_MILLIS, "the cancelled collector stopped after $millis ms")
            media.readersKept(core, "numbers")?.let { assertEquals(0L, it, "readers kept after the collector was cancelled") }
            events.publish(2)
            assertEquals(listOf(1, 2), withTimeout(WAIT_MILLIS) { source.asFlow().take(2).toList() })
        }
    }

    /**
     * `Source.asFlow()` collected before the core's start: where the media lets a read wait for
     * the start (Liberty, Radiant), the flow emits once the core runs; where it refuses reads before
     * `start()` (Optimus), the collection fails at once with that `IllegalStateException`.
     */
    @Test
    fun `a source's flow collected before the start waits for it or fails at once as the media's reads do`() = runBlocking {
        media.newCore().use { core ->
            val events = EventBlock<Int>()
            val source = core.source("numbers", events)
            if (media.refusesReadsBeforeStart) {
                val began = System.nanoTime()
                val failure = assertThrows<IllegalStateException> {
                    runBlocking { withTimeout(WAIT_MILLIS) { source.asFlow().first() } }
                }
                val millis = (System.nanoTime() - began) / 1_000_000
                assertTrue(failure.message!!.contains("start()"), failure.message)
                assertTrue(millis < PROMPT_MILLIS * 4, "the collection failed after $millis ms")
                core.start()
                events.publish(5)
                assertEquals(5, withTimeout(WAIT_MILLIS) { source.asFlow().first() }, "a collection after the start")
            } else {
                val first = async(Dispatchers.IO) { source.asFlow().first() }
                core.start()
                events.publish(5)
                assertEquals(5, withTimeout(WAIT_MILLIS) { first.await() })
            }
        }
    }

    @Test
    fun `a flow feeds a source from the core's start, on every reader`() = runBlocking {
        media.newCore().use { core ->
            val ticks = core.source("ticks", flowOf(1, 2, 3))
            val doubled = ticks.then(core.chain("double") { x: Int -> x * 2 })
            core.start()
            doubled.reader().use { reader ->
                assertEquals(listOf(2, 4, 6), List(3) { reader.take(Duration.ofMillis(WAIT_MILLIS)).orElseThrow() })
            }
            // declared on a started core: collected at once
            val late = core.source(flowOf("a", "b"))
            late.reader().use { reader ->
                assertEquals(listOf("a", "b"), List(2) { reader.take(Duration.ofMillis(WAIT_MILLIS)).orElseThrow() })
            }
        }
    }

    @Test
    fun `closing the core cancels the flow that feeds a source`() = runBlocking {
        val collecting = CountDownLatch(1)
        val cancelled = CountDownLatch(1)
        val endless = flow {
            try {
                emit(1)
                collecting.countDown()
                awaitCancellation()
            } finally {
                cancelled.countDown()
            }
        }
        val core = media.newCore()
        val source = core.source("endless", endless)
        core.start()
        source.reader().use { assertEquals(1, it.take(Duration.ofMillis(WAIT_MILLIS)).orElseThrow()) }
        assertTrue(collecting.await(WAIT_MILLIS, TimeUnit.MILLISECONDS))
        core.close()
        assertTrue(cancelled.await(WAIT_MILLIS, TimeUnit.MILLISECONDS), "the flow was not cancelled by close()")
    }

    @Test
    fun `a failing flow goes to the core's error handler under the source's name`() = runBlocking {
        val failures = ArrayBlockingQueue<Triple<String, Any, Throwable>>(4)
        val config = CoreConfig.builder().errorHandler { service, input, error -> failures.add(Triple(service, input, error)) }.build()
        media.newCore(config).use { core ->
            val boom = IllegalStateException("sensor unplugged")
            val failing = flow {
                emit(1)
                throw boom
            }
            val source = core.source("sensor", failing)
            core.start()
            source.reader().use { assertEquals(1, it.take(Duration.ofMillis(WAIT_MILLIS)).orElseThrow()) }
            val failure = failures.poll(WAIT_MILLIS, TimeUnit.MILLISECONDS) ?: error("no failure reached the error handler")
            assertEquals("sensor", failure.first)
            assertSame(failing, failure.second)
            assertSame(boom, failure.third)
        }
    }

    /**
     * `PrimeCore.source(name, flow)`: once its flow has completed, or failed, the source publishes
     * nothing more, and stays: it does not complete, so its readers wait on (a take times out
     * rather than ending as at a close), and a reader made afterwards gets the values the source
     * retains.
     */
    @Test
    fun `a source whose flow completed or failed publishes nothing more and stays`() = runBlocking {
        val failures = ArrayBlockingQueue<Throwable>(4)
        val config = CoreConfig.builder().errorHandler { _, _, error -> failures.add(error) }.build()
        media.newCore(config).use { core ->
            val done = core.source("done", flowOf(1, 2))
            val failed = core.source("failed", flow { emit(10); throw IllegalStateException("sensor unplugged") })
            val doneReader = done.reader()
            val failedReader = failed.reader()
            core.start()
            assertEquals(listOf(1, 2), List(2) { doneReader.take(Duration.ofMillis(WAIT_MILLIS)).orElseThrow() })
            assertEquals(10, failedReader.take(Duration.ofMillis(WAIT_MILLIS)).orElseThrow())
            assertInstanceOf(
                IllegalStateException::class.java,
                failures.poll(WAIT_MILLIS, TimeUnit.MILLISECONDS) ?: error("the failed flow never reached the error handler"),
            )
            for ((name, reader) in listOf("done" to doneReader, "failed" to failedReader)) {
                // a completed source would end the take with CoreClosedException; this one stays
                assertEquals(Optional.empty<Int>(), reader.take(Duration.ofMillis(NOT_BEFORE_MILLIS)), "$name: nothing more")
            }
            done.reader().use { late ->
                assertEquals(listOf(1, 2), List(2) { late.take(Duration.ofMillis(WAIT_MILLIS)).orElseThrow() }, "a later reader")
                assertEquals(Optional.empty<Int>(), late.take(Duration.ofMillis(NOT_BEFORE_MILLIS)), "a later reader: nothing more")
            }
            doneReader.close()
            failedReader.close()
        }
    }

    /**
     * A value of the flow that cannot be published (a codec refuses it) goes to the core's error
     * handler under the source's name with that value as the input, and collection carries on
     * with the next value (`PrimeCore.source(name, flow)`; README, Kotlin).
     */
    @Test
    fun `a value that cannot be published goes to the error handler with that value and the flow carries on`() = runBlocking {
        val failures = ArrayBlockingQueue<Triple<String, Any, Throwable>>(4)
        val config = CoreConfig.builder()
            .copyValues(IntsOnly) // Liberty and Radiant copy through it; Optimus through its own codec
            .errorHandler { service, input, error -> failures.add(Triple(service, input, error)) }
            .build()
        media.newCore(config).use { core ->
            val refused = Unshippable()
            val source = core.source("sensor", flowOf<Any>(1, refused, 3))
            core.start()
            source.reader().use { reader ->
                assertEquals(listOf<Any>(1, 3), List(2) { reader.take(Duration.ofMillis(WAIT_MILLIS)).orElseThrow() })
            }
            val failure = failures.poll(WAIT_MILLIS, TimeUnit.MILLISECONDS) ?: error("no failure reached the error handler")
            assertEquals("sensor", failure.first)
            assertSame(refused, failure.second)
            assertInstanceOf(IllegalArgumentException::class.java, failure.third)
            assertEquals(null, failures.poll(), "one failure only")
        }
    }

    /**
     * `PrimeCore.source(name, flow)`: the flow is collected once, from the core's start (not when
     * the source is declared).
     */
    @Test
    fun `a flow is collected once, from the core's start and not before`() = runBlocking {
        val collections = AtomicInteger()
        val collecting = CountDownLatch(1)
        val counted = flow {
            collections.incrementAndGet()
            collecting.countDown()
            emit(1)
            emit(2)
        }
        val core = media.newCore()
        val source = core.source("counted", counted)
        val reader = source.reader()
        assertFalse(collecting.await(NOT_BEFORE_MILLIS, TimeUnit.MILLISECONDS), "the flow was collected before start()")
        core.start()
        assertEquals(listOf(1, 2), List(2) { reader.take(Duration.ofMillis(WAIT_MILLIS)).orElseThrow() })
        core.close()
        assertEquals(1, collections.get(), "collections of the flow")
    }

    /** `PrimeCore.source(flow)`: a source without a name is named `source-N`, as an event block's. */
    @Test
    fun `a flow's source without a name is named source-N`() {
        media.newCore().use { core ->
            val first = core.source(flowOf(1))
            val second = core.source(flowOf(2))
            assertTrue(first.name().matches(Regex("source-\\d+")), first.name())
            assertTrue(second.name().matches(Regex("source-\\d+")), second.name())
            assertNotEquals(first.name(), second.name())
        }
    }

    /** `PrimeCore.source(name, flow)` on a closed core throws `CoreClosedException` and collects nothing. */
    @Test
    fun `a flow's source declared on a closed core is refused with CoreClosedException`() {
        val collected = AtomicInteger()
        val core = media.newCore()
        core.start()
        core.close()
        assertThrows<CoreClosedException> { core.source("late", flow { collected.incrementAndGet(); emit(1) }) }
        assertThrows<CoreClosedException> { core.source(flow { collected.incrementAndGet(); emit(1) }) }
        assertEquals(0, collected.get())
    }

    /**
     * A flow that fails with a cancellation of its own (a `withTimeout` inside it that runs out),
     * while the core runs, has failed: the failure goes to the error handler with the flow as the
     * input, as any other failure of the flow, rather than ending the source without a word.
     */
    @Test
    fun `a flow that fails with a cancellation of its own goes to the error handler`(): Unit = runBlocking {
        val failures = ArrayBlockingQueue<Triple<String, Any, Throwable>>(4)
        val config = CoreConfig.builder().errorHandler { service, input, error -> failures.add(Triple(service, input, error)) }.build()
        media.newCore(config).use { core ->
            val timingOut = flow {
                emit(1)
                withTimeout(1) { awaitCancellation() }
            }
            val source = core.source("sensor", timingOut)
            core.start()
            source.reader().use { assertEquals(1, it.take(Duration.ofMillis(WAIT_MILLIS)).orElseThrow()) }
            val failure = failures.poll(WAIT_MILLIS, TimeUnit.MILLISECONDS) ?: error("the flow's failure never reached the error handler")
            assertEquals("sensor", failure.first)
            assertSame(timingOut, failure.second)
            assertInstanceOf(TimeoutCancellationException::class.java, failure.third)
        }
    }

    /**
     * A flow that calls a suspending block whose own `withTimeout` runs out fails with the block's
     * [BlockCancelledException]: the failure goes to the error handler with the flow as the input,
     * as any other failure of the flow.
     */
    @Test
    fun `a flow whose suspending call fails with the block's own timeout goes to the error handler`(): Unit = runBlocking {
        val failures = ArrayBlockingQueue<Triple<String, Any, Throwable>>(4)
        val config = CoreConfig.builder().errorHandler { service, input, error -> failures.add(Triple(service, input, error)) }.build()
        media.newCore(config).use { core ->
            val timingOut = suspendingBlock<Int, Int> { x -> if (x < 0) withTimeout(1) { awaitCancellation() } else x }
            val calling = flowOf(1, -1, 2).map { timingOut.processSuspending(it) }
            val source = core.source("sensor", calling)
            core.start()
            source.reader().use { assertEquals(1, it.take(Duration.ofMillis(WAIT_MILLIS)).orElseThrow()) }
            val failure = failures.poll(WAIT_MILLIS, TimeUnit.MILLISECONDS) ?: error("the flow's failure never reached the error handler")
            assertEquals("sensor", failure.first)
            assertSame(calling, failure.second)
            assertInstanceOf(BlockCancelledException::class.java, failure.third, "what the error handler got")
            assertInstanceOf(TimeoutCancellationException::class.java, failure.third.cause, "the block's timeout")
        }
    }

    /**
     * A source's flow collected in a `launch` and handed to a suspending block whose own
     * `withTimeout` runs out: the collection fails with the block's [BlockCancelledException], so
     * the `launch` fails rather than ending as if cancelled.
     */
    @Test
    fun `a source's flow whose collector's suspending call times out of its own fails the launch`(): Unit = runBlocking {
        media.newCore().use { core ->
            val events = EventBlock<Int>()
            val source = core.source("numbers", events)
            core.start()
            val timingOut = suspendingBlock<Int, Int> { x -> if (x < 0) withTimeout(1) { awaitCancellation() } else x }
            val seen = Channel<Int>(Channel.UNLIMITED)
            val collecting = async(Dispatchers.IO) {
                failureOfLaunch { source.asFlow().collect { seen.send(timingOut.processSuspending(it)) } }
            }
            events.publish(1)
            assertEquals(1, withTimeout(WAIT_MILLIS) { seen.receive() })
            events.publish(-1)
            val failure = withTimeout(WAIT_MILLIS) { collecting.await() }
            assertInstanceOf(BlockCancelledException::class.java, failure, "what the collecting launch failed with")
            assertInstanceOf(TimeoutCancellationException::class.java, failure!!.cause, "the block's timeout")
        }
    }

    /**
     * An error handler that throws is logged and ignored, as everywhere in the core
     * (`ErrorHandler`): the flow carries on with its next value.
     */
    @Test
    fun `an error handler that throws does not end the flow`(): Unit = runBlocking {
        val handled = AtomicInteger()
        val config = CoreConfig.builder()
            .copyValues(IntsOnly)
            .errorHandler { _, _, _ -> handled.incrementAndGet(); throw IllegalStateException("the handler fails too") }
            .build()
        media.newCore(config).use { core ->
            val source = core.source("sensor", flowOf<Any>(1, Unshippable(), 3))
            core.start()
            source.reader().use { reader ->
                assertEquals(1, reader.take(Duration.ofMillis(WAIT_MILLIS)).orElseThrow())
                assertEquals(Optional.of<Any>(3), reader.take(Duration.ofMillis(WAIT_MILLIS)), "the value after the refused one")
            }
            assertEquals(1, handled.get(), "calls of the error handler")
        }
    }

    /**
     * `close()` stops the core's work before it returns, the flow that feeds a source included:
     * once it returns, the flow's own clean-up (a `finally`, an `awaitClose`) has run.
     */
    @Test
    fun `close returns once the flow that feeds a source has ended`() {
        val collecting = CountDownLatch(1)
        val cleanupBegan = CountDownLatch(1)
        val finishCleanup = CountDownLatch(1)
        val cleanedUp = CountDownLatch(1)
        val feed = flow {
            try {
                emit(1)
                collecting.countDown()
                awaitCancellation()
            } finally {
                cleanupBegan.countDown()
                finishCleanup.await(WAIT_MILLIS, TimeUnit.MILLISECONDS)
                cleanedUp.countDown()
            }
        }
        val core = media.newCore()
        core.source("sensor", feed)
        core.start()
        assertTrue(collecting.await(WAIT_MILLIS, TimeUnit.MILLISECONDS), "the flow was not collected")
        val closed = CountDownLatch(1)
        val cleanedWhenClosed = AtomicBoolean()
        val closer = Thread {
            core.close()
            cleanedWhenClosed.set(cleanedUp.count == 0L)
            closed.countDown()
        }
        closer.start()
        assertTrue(cleanupBegan.await(WAIT_MILLIS, TimeUnit.MILLISECONDS), "close() did not cancel the flow")
        val returnedDuringCleanup = closed.await(CLEANUP_MILLIS, TimeUnit.MILLISECONDS)
        finishCleanup.countDown()
        assertTrue(closed.await(WAIT_MILLIS, TimeUnit.MILLISECONDS), "close() did not return")
        assertFalse(returnedDuringCleanup, "close() returned while the flow was still cleaning up")
        assertTrue(cleanedWhenClosed.get(), "the flow had not ended when close() returned")
    }

    /**
     * A flow that does not end when cancelled holds `close()` up for the core's shutdown timeout at
     * most, and the error handler is told, under the source's name, that it goes on.
     */
    @Test
    fun `a flow that ignores its cancellation holds close up for the shutdown timeout at most, and the error handler is told`() {
        val failures = ArrayBlockingQueue<Triple<String, Any, Throwable>>(4)
        val config = CoreConfig.builder()
            .shutdownTimeout(Duration.ofMillis(CLEANUP_MILLIS))
            .errorHandler { service, input, error -> failures.add(Triple(service, input, error)) }
            .build()
        val collecting = CountDownLatch(1)
        val release = CountDownLatch(1)
        val stubborn = flow {
            emit(1)
            collecting.countDown()
            release.await(WAIT_MILLIS, TimeUnit.MILLISECONDS) // ignores the cancellation
        }
        try {
            val core = media.newCore(config)
            core.source("stubborn", stubborn)
            core.start()
            assertTrue(collecting.await(WAIT_MILLIS, TimeUnit.MILLISECONDS), "the flow was not collected")
            val began = System.nanoTime()
            core.close()
            val millis = (System.nanoTime() - began) / 1_000_000
            assertTrue(millis < WAIT_MILLIS / 2, "close() took $millis ms")
            val failure = failures.poll(WAIT_MILLIS, TimeUnit.MILLISECONDS) ?: error("the error handler was not told")
            assertEquals("stubborn", failure.first)
            assertEquals("close", failure.second)
            assertTrue(failure.third.message!!.contains("did not end within"), failure.third.message)
        } finally {
            release.countDown()
        }
    }

    /** A flow may close its own core (its last value sent, say): the close does not wait for the flow that makes it. */
    @Test
    fun `a flow that closes its own core is not held up waiting for itself`() {
        val config = CoreConfig.builder().shutdownTimeout(Duration.ofMillis(WAIT_MILLIS * 2)).build()
        val core = media.newCore(config)
        val closedItself = CountDownLatch(1)
        core.source("last", flow {
            emit(1)
            core.close()
            closedItself.countDown()
        })
        core.start()
        assertTrue(closedItself.await(WAIT_MILLIS, TimeUnit.MILLISECONDS), "the flow's close() of its own core did not return")
        core.close()
    }

    /**
     * `PrimeCore.source(name, flow)`: an error handler that closes the core when the flow fails
     * (it runs on the flow's collection) is not held up waiting for that collection to end.
     */
    @Test
    fun `an error handler that closes the core on the flow's failure is not held up waiting for the flow`() {
        val closing = AtomicReference<dev.prime.PrimeCore>()
        val closedItself = CountDownLatch(1)
        val config = CoreConfig.builder()
            .shutdownTimeout(Duration.ofMillis(WAIT_MILLIS * 2))
            .errorHandler { _, _, _ ->
                closing.get().close()
                closedItself.countDown()
            }
            .build()
        val core = media.newCore(config)
        closing.set(core)
        core.source("failing", flow<Int> {
            emit(1)
            throw IllegalStateException("sensor unplugged")
        })
        core.start()
        assertTrue(
            closedItself.await(WAIT_MILLIS, TimeUnit.MILLISECONDS),
            "the error handler's close() of the core did not return",
        )
        assertTrue(core.isClosed, "the core is closed")
        core.close()
    }

    /**
     * `PrimeCore.source(name, flow)`: a value whose publish throws an `Error` that is no
     * `VirtualMachineError` (here a codec's `AssertionError`) is a value that cannot be published,
     * as for the core's services (architecture, Errors): it goes to the error handler with that
     * value and that error, and collection carries on with the next value.
     */
    @Test
    fun `a value whose publish throws an Error that is no VirtualMachineError goes to the error handler and the flow carries on`(): Unit = runBlocking {
        val failures = ArrayBlockingQueue<Triple<String, Any, Throwable>>(4)
        val config = CoreConfig.builder()
            .copyValues(CheckingCodec)
            .errorHandler { service, input, error -> failures.add(Triple(service, input, error)) }
            .build()
        media.newCoreWithCodec(config).use { core ->
            val source = core.source("sensor", flowOf(1, CheckingCodec.FAILS_ITS_CHECK, 3))
            core.start()
            source.reader().use { reader ->
                val failure = failures.poll(WAIT_MILLIS, TimeUnit.MILLISECONDS) ?: error("no failure reached the error handler")
                assertEquals(CheckingCodec.FAILS_ITS_CHECK, failure.second, "the input the error handler got")
                assertEquals("sensor", failure.first)
                assertInstanceOf(AssertionError::class.java, failure.third, "what the error handler got")
                assertEquals(listOf(1, 3), List(2) { reader.take(Duration.ofMillis(WAIT_MILLIS)).orElseThrow() })
            }
            assertEquals(null, failures.poll(), "one failure only")
        }
    }

    /**
     * `PrimeCore.source(name, flow)`: a `VirtualMachineError` the flow throws ends the collection,
     * as it ends a core's service: never silently (an ERROR line names the source and the error),
     * not through the error handler, and the core still closes.
     */
    @Test
    fun `a VirtualMachineError from the flow ends the collection with an ERROR line naming the source`(): Unit = runBlocking {
        val failures = ArrayBlockingQueue<Throwable>(4)
        val config = CoreConfig.builder().errorHandler { _, _, error -> failures.add(error) }.build()
        CapturedStderr().use { stderr ->
            media.newCore(config).use { core ->
                val source = core.source("deep", flow {
                    emit(1)
                    throw StackOverflowError("thrown by the flow")
                })
                source.reader().use { reader ->
                    core.start()
                    assertEquals(1, reader.take(Duration.ofMillis(WAIT_MILLIS)).orElseThrow())
                    val line = stderr.awaitLine({ it.isStopLineOf("deep") }, Duration.ofMillis(WAIT_MILLIS)).orElse(null)
                    assertTrue(line != null && "thrown by the flow" in line, "the ERROR line: $line")
                }
            }
        }
        assertEquals(null, failures.poll(), "the error handler does not get it")
    }

    private fun String.isStopLineOf(source: String): Boolean =
        "ERROR" in this && "the flow feeding source '$source'" in this && "stops: java.lang.StackOverflowError" in this

    /**
     * `PrimeCore.source(name, flow)`: an interrupt flag on the collecting thread is not the core's
     * close. A flag the flow's own code left set is cleared before the next publish, so that value
     * is published (here a codec that waits for a pooled buffer would otherwise fail on it); a
     * publish that ends with an `InterruptedException` while the core runs (a codec that
     * interrupted its own thread) goes to the error handler as that `InterruptedException`, the
     * very object, with the value, and collection carries on.
     */
    @Test
    fun `a stray interrupt on the collecting thread loses no value, and a publish's InterruptedException reaches the error handler as it is`(): Unit = runBlocking {
        val failures = ArrayBlockingQueue<Triple<String, Any, Throwable>>(4)
        val codec = PooledBufferCodec()
        val config = CoreConfig.builder()
            .copyValues(codec)
            .errorHandler { service, input, error -> failures.add(Triple(service, input, error)) }
            .build()
        media.newCoreWithCodec(config).use { core ->
            val interrupting = flow {
                emit(1)
                Thread.currentThread().interrupt() // as a blocking call that restored the flag would leave it
                emit(2)
                emit(PooledBufferCodec.INTERRUPTS_ITSELF)
                emit(3)
            }
            val source = core.source("sensor", interrupting)
            core.start()
            source.reader().use { reader ->
                val failure = failures.poll(WAIT_MILLIS, TimeUnit.MILLISECONDS) ?: error("no failure reached the error handler")
                assertEquals(PooledBufferCodec.INTERRUPTS_ITSELF, failure.second, "the input the error handler got (${failure.third})")
                assertEquals("sensor", failure.first)
                assertSame(codec.interrupted.get(), failure.third, "what the error handler got")
                assertEquals(listOf(1, 2, 3), List(3) { reader.take(Duration.ofMillis(WAIT_MILLIS)).orElseThrow() })
            }
            assertEquals(null, failures.poll(), "one failure only")
        }
    }

    /**
     * `Source.asFlow()`: only the collector's cancellation and the core's close end the reader's
     * wait. An interrupt flag left set on the thread the reader takes on (set right before the
     * first take, with nothing published, so the take must wait and meets it at once) is not the
     * collector's cancellation: the take is retried and the flow emits the next value, rather
     * than ending as if cancelled.
     */
    @Test
    fun `a source's flow whose take meets a stray interrupt takes again and emits the next value`(): Unit = runBlocking {
        media.newCore().use { core ->
            val events = EventBlock<Int>()
            val strayed = StrayFlagSource(core.source("numbers", events))
            core.start()
            val collecting = async(Dispatchers.IO) { runCatching { strayed.asFlow().first() } }
            // nothing is published before the flow takes again after the stray interrupt, or ended
            collecting.invokeOnCompletion { strayed.tookAgain.complete(Unit) }
            withTimeout(WAIT_MILLIS) { strayed.tookAgain.await() }
            events.publish(1)
            val outcome = withTimeout(WAIT_MILLIS) { collecting.await() }
            assertEquals(1, outcome.getOrNull(), "what the flow emitted after a stray interrupt (it ended with ${outcome.exceptionOrNull()})")
        }
    }

    /** A type no codec knows. */
    private class Unshippable

    /** A copying codec that carries `Int`s only, refusing anything else as a codec refuses an unknown type. */
    private object IntsOnly : ValueCodec {
        override fun encode(value: Any): ByteArray {
            require(value is Int) { "${value.javaClass.name} cannot be copied: only Int" }
            return ByteBuffer.allocate(Int.SIZE_BYTES).putInt(value).array()
        }

        override fun decode(bytes: ByteArray): Any = ByteBuffer.wrap(bytes).int
    }

    /** A codec of `Int`s whose own check of a value fails with an [AssertionError], as a broken invariant would. */
    private object CheckingCodec : ValueCodec {
        /** The value whose check fails. */
        const val FAILS_ITS_CHECK = -1

        override fun encode(value: Any): ByteArray {
            if (value == FAILS_ITS_CHECK) throw AssertionError("the codec's check of $value failed")
            return IntsOnly.encode(value)
        }

        override fun decode(bytes: ByteArray): Any = IntsOnly.decode(bytes)
    }

    /**
     * A codec of `Int`s that borrows its one buffer from a pool, waiting for it interruptibly (an
     * interrupt flag makes it throw [InterruptedException]); for [INTERRUPTS_ITSELF] it interrupts
     * its own thread first, and keeps the exception it then throws.
     */
    private class PooledBufferCodec : ValueCodec {
        private val pool = ArrayBlockingQueue<ByteBuffer>(1).apply { add(ByteBuffer.allocate(Int.SIZE_BYTES)) }
        val interrupted = AtomicReference<InterruptedException>()

        override fun encode(value: Any): ByteArray {
            require(value is Int) { "${value.javaClass.name} cannot be copied: only Int" }
            if (value == INTERRUPTS_ITSELF) Thread.currentThread().interrupt()
            val buffer = try {
                pool.take()
            } catch (e: InterruptedException) {
                interrupted.set(e)
                throw e
            }
            try {
                return buffer.clear().putInt(value).array().copyOf()
            } finally {
                pool.add(buffer)
            }
        }

        override fun decode(bytes: ByteArray): Any = ByteBuffer.wrap(bytes).int

        companion object {
            const val INTERRUPTS_ITSELF = -2
        }
    }

    /**
     * A real source whose reader's first take finds the thread's interrupt flag set, as other code
     * on a pooled thread may leave it; [tookAgain] completes when the reader takes a second time.
     */
    private class StrayFlagSource<T>(private val real: Source<T>) : Source<T> by real {
        val tookAgain = CompletableDeferred<Unit>()
        private val takes = AtomicInteger()

        override fun reader(): Reader<T> = StrayFlagReader(real.reader())

        private inner class StrayFlagReader(private val reader: Reader<T>) : Reader<T> by reader {
            override fun take(): T {
                when (takes.incrementAndGet()) {
                    1 -> Thread.currentThread().interrupt()
                    2 -> tookAgain.complete(Unit)
                }
                return reader.take()
            }
        }
    }

    private companion object {
        const val WAIT_MILLIS = 20_000L
        const val PROMPT_MILLIS = 750L

        /** How long a flow's clean-up holds `close()` up in the tests of a close that waits for it. */
        const val CLEANUP_MILLIS = 500L

        /** How long a flow must stay uncollected before start() to count as not collected early. */
        const val NOT_BEFORE_MILLIS = 300L
    }
}

internal class LibertyFlowTest : FlowKit(Liberty)

internal class RadiantFlowTest : FlowKit(Radiant)

internal class OptimusFlowTest : FlowKit(Optimus)

internal class OptimusSlowRedisFlowTest : FlowKit(OptimusSlowRedis)

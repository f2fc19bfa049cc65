@file:JvmName("FlowSources")

package dev.prime.kotlin

import dev.prime.EventBlock
import dev.prime.FailureReport
import dev.prime.PrimeCore
import dev.prime.Source
import kotlinx.coroutines.CancellationException
import kotlinx.coroutines.CoroutineName
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.SupervisorJob
import kotlinx.coroutines.asContextElement
import kotlinx.coroutines.cancel
import kotlinx.coroutines.currentCoroutineContext
import kotlinx.coroutines.ensureActive
import kotlinx.coroutines.flow.Flow
import kotlinx.coroutines.job
import kotlinx.coroutines.launch
import kotlinx.coroutines.runInterruptible
import org.slf4j.LoggerFactory
import java.time.Duration
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * A source, named `source-N`, that publishes the values of [flow]; see [source] with a name.
 *
 * @param flow the values to publish, collected while the core runs
 * @return a new source of this core
 */
@JvmSynthetic // Java calls sourceFromJava, under the name source
@JvmName("sourceOfFlow")
public fun <T : Any> PrimeCore.source(flow: Flow<T>): Source<T> = feed(EventBlock(), flow) { source(it) }

/**
 * A source named [name] that publishes the values of [flow]: an event block fed by the flow. The
 * flow is collected once, on [Dispatchers.IO], in a coroutine scope tied to this core: collection
 * begins when the core starts (at once if it has started) and is cancelled when the core closes,
 * whose `close()` waits for it to end (the flow's own clean-up, such as a `finally` or an
 * `awaitClose`, run), as for the core's services at most its `shutdownTimeout`; a flow that has
 * not ended by then is reported to the error handler under the source's name, with `"close"` as
 * the input. A close from within the flow (or from the error handler it calls) does not wait.
 * When the flow completes, the source publishes nothing more; the source itself stays (sources do
 * not complete).
 *
 * Failures go to the core's error handler under the source's name: a value that cannot be
 * published (such as a value an Optimus codec refuses) with that value as the input, after which
 * collection carries on with the next value (whatever the publish throws, an `Error` such as an
 * `AssertionError` included, as for the core's services); a failure of the flow itself with the
 * flow as the input, after which the source publishes nothing more. A cancellation the flow
 * throws while the core runs (a `withTimeout` in it that runs out) is such a failure. As
 * everywhere in the core, an error handler that throws is logged and ignored, and collection goes
 * on. A `VirtualMachineError` (from the flow or a publish) is neither: as for the core's
 * services, it ends the collection, the error handler does not get it, and it is logged at ERROR
 * as `the flow feeding source '<name>' of core '<core>' stops: <the error>`.
 *
 * An interrupt flag on the collecting thread is not the core's close, which cancels the
 * collection: a flag the flow's own code leaves set (a blocking call in it that restored the
 * flag, as is customary) is cleared before the next publish, and one a publish leaves after it,
 * as the core's services clear the flag a block leaves; so the value is published, and the flag
 * reaches neither the flow's later code nor other work on [Dispatchers.IO]. A publish that ends
 * with an [InterruptedException] while the core runs (a codec interrupted in a wait of its own)
 * has failed like any other: the error handler gets that `InterruptedException`, the very object
 * (not the cancellation `runInterruptible` would make of it), with the value as the input, and
 * collection goes on.
 *
 * From Java these are `FlowSources.source(core, name, flow)` and `FlowSources.source(core, flow)`,
 * which refuse a `null` argument with a [NullPointerException] naming it and saying what to pass,
 * as the core's declarations refuse a `null` (Kotlin callers cannot pass one); nothing is declared
 * then.
 *
 * @param name the source's name, unique in this core
 * @param flow the values to publish, collected while the core runs
 * @return a new source of this core
 * @throws dev.prime.CoreClosedException if the core is closed
 */
@JvmSynthetic // Java calls sourceFromJava, under the name source
@JvmName("sourceOfFlow")
public fun <T : Any> PrimeCore.source(name: String, flow: Flow<T>): Source<T> =
    feed(EventBlock(), flow) { source(name, it) }

/**
 * [source] as Java sees it, `FlowSources.source(core, flow)`: internal, so not part of the Kotlin
 * API, and with nullable parameters, so that a `null` from Java is refused by the checks here,
 * naming the parameter and what to pass, not by the check Kotlin makes of a non-null parameter.
 */
@JvmName("source")
internal fun <T : Any> sourceFromJava(core: PrimeCore?, flow: Flow<T>?): Source<T> =
    checkedCore(core, "source(core, flow)").source(checkedFlow(flow, "source(core, flow)"))

/** [source] with a name as Java sees it, `FlowSources.source(core, name, flow)` (see the other). */
@JvmName("source")
internal fun <T : Any> sourceFromJava(core: PrimeCore?, name: String?, flow: Flow<T>?): Source<T> {
    val what = "source(core, name, flow)"
    val checkedCore = checkedCore(core, what)
    if (name == null) {
        throw NullPointerException("FlowSources.$what: name must not be null; pass the source's name, unique in its core")
    }
    return checkedCore.source(name, checkedFlow(flow, what))
}

private fun checkedCore(core: PrimeCore?, what: String): PrimeCore = core
    ?: throw NullPointerException("FlowSources.$what: core must not be null; pass the PrimeCore the source belongs to")

private fun <T : Any> checkedFlow(flow: Flow<T>?, what: String): Flow<T> = flow
    ?: throw NullPointerException(
        "FlowSources.$what: flow must not be null; pass the Flow whose values the source publishes " +
            "(flowOf() for none)",
    )

private inline fun <T : Any> PrimeCore.feed(
    events: EventBlock<T>,
    flow: Flow<T>,
    declare: (EventBlock<T>) -> Source<T>,
): Source<T> {
    val source = declare(events)
    val feed = FlowFeed(this, source.name(), flow, events)
    whenRunning(source.name(), feed::start, feed::stop)
    return source
}

/** Where a flow source that a `VirtualMachineError` ends says so, as the core's services do. */
private val LOG = LoggerFactory.getLogger(FlowFeed::class.java)

/** The [FlowFeed] whose collection runs on this thread, if any. */
private val feeding = ThreadLocal<FlowFeed<*>>()

/** The longest wait [FlowFeed.stop] reckons in nanoseconds (about 292 years). */
private val LONGEST_WAIT: Duration = Duration.ofNanos(Long.MAX_VALUE)

/**
 * Collects a flow into an event block while a core runs.
 *
 * Design note. The scope has its own [SupervisorJob], cancelled by the core's close hook; a
 * launch on a cancelled scope does nothing, so a close that overtakes the start leaves nothing
 * running. Publishing may wait (an Optimus source publishes over the network), so it runs
 * interruptibly on [Dispatchers.IO], and a cancellation during a publish ends it at once. The
 * close hook then waits for the job to complete (the flow's own clean-up run), as the core waits
 * for its services, at most the core's shutdown timeout; not when the close comes from the
 * collection itself (the flow or the error handler closing the core), which [feeding] tells.
 */
private class FlowFeed<T : Any>(
    private val core: PrimeCore,
    private val name: String,
    private val flow: Flow<T>,
    private val events: EventBlock<T>,
) {
    private val scope = CoroutineScope(
        SupervisorJob() + Dispatchers.IO + CoroutineName("prime-${core.name()}-$name") + feeding.asContextElement(this),
    )
    private val ended = CountDownLatch(1)

    init {
        scope.coroutineContext.job.invokeOnCompletion { ended.countDown() }
    }

    fun start() {
        scope.launch { collect() }
    }

    fun stop() {
        scope.cancel("core '${core.name()}' closed")
        if (feeding.get() === this) {
            return // the collection closes the core: it ends once that close returns
        }
        val timeout = core.config().shutdownTimeout()
        val endedInTime = try {
            ended.await(if (timeout < LONGEST_WAIT) timeout.toNanos() else Long.MAX_VALUE, TimeUnit.NANOSECONDS)
        } catch (_: InterruptedException) {
            Thread.currentThread().interrupt() // the close's caller gave up waiting
            return
        }
        if (!endedInTime) {
            val stillRunning = IllegalStateException(
                "the flow feeding source '$name' did not end within the shutdown timeout ($timeout) after" +
                    " core '${core.name()}' began to close, and goes on in the background: make it honour" +
                    " cancellation (wrap a blocking call in it in runInterruptible, check isActive in a long loop)",
            )
            FailureReport.report(core.config().errorHandler(), name, "close", stillRunning)
        }
    }

    private suspend fun collect() {
        val errors = core.config().errorHandler()
        try {
            flow.collect { value ->
                Thread.interrupted() // a flag the flow's own code left: the core's close cancels, it does not interrupt here
                try {
                    runInterruptible { publish(value) }
                } catch (fatal: VirtualMachineError) {
                    throw fatal
                } catch (failure: Throwable) { // an AssertionError of a codec too, as in the core's services
                    currentCoroutineContext().ensureActive() // the core closed during the publish
                    FailureReport.report(errors, name, value, if (failure is InterruptedPublish) failure.cause else failure)
                } finally {
                    Thread.interrupted() // a flag the publish left (runInterruptible clears only the one it set)
                }
            }
        } catch (fatal: VirtualMachineError) {
            LOG.error("the flow feeding source '{}' of core '{}' stops: {}", name, core.name(), fatal.toString())
            throw fatal
        } catch (failure: Throwable) {
            if (failure is CancellationException) {
                // the core's close, unless the flow threw a cancellation of its own (a withTimeout in it)
                currentCoroutineContext().ensureActive()
            }
            FailureReport.report(errors, name, flow, failure)
        }
    }

    /**
     * Publishes [value], carrying an [InterruptedException] out of `runInterruptible` as an
     * [InterruptedPublish]: `runInterruptible` turns it into a cancellation whatever interrupted
     * the thread, and [collect] tells the core's close from a failure of the publish itself.
     */
    private fun publish(value: T) {
        try {
            events.publish(value)
        } catch (interrupted: InterruptedException) { // a codec's own wait, thrown as Kotlin may
            throw InterruptedPublish(interrupted)
        }
    }
}

/** An [InterruptedException] a publish threw, carried out of `runInterruptible` as it is. */
private class InterruptedPublish(override val cause: InterruptedException) : RuntimeException(cause) {
    private companion object {
        private const val serialVersionUID: Long = 1L
    }
}

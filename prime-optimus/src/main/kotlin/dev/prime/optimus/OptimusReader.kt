package dev.prime.optimus

import dev.prime.CoreClosedException
import dev.prime.Reader
import dev.prime.internal.Deadlines.boundedNanos
import dev.prime.internal.RateLimitedLog
import org.slf4j.LoggerFactory
import java.nio.channels.ClosedByInterruptException
import java.time.Duration
import java.util.Optional
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicBoolean
import java.util.concurrent.locks.ReentrantLock

/**
 * A reader of an [OptimusSource]: its own Redis list, which the source fills and trims to the
 * retention (counting what it trims in a `:missed` counter).
 *
 * Design note. A taken value is first moved to the reader's processing list and removed from it
 * only with the next operation, so a connection lost between Redis sending a value and this
 * reader receiving it loses nothing: after reconnecting the reader reads its processing list
 * again and skips, by id, what it had already handed out. All reads take turns on the reader's
 * lock (the [Reader] contract allows concurrent calls), except that a [poll] or [drain] that finds
 * a take of another thread waiting for a value returns empty at once, and one that finds it
 * waiting for Redis throws [RedisUnavailableException] at once; a blocked [take] is woken by closing the
 * core or the reader, which close its connection and end its pause between round trips (a backoff
 * while Redis is unreachable, a deadline's last moment), and by an interrupt, which aborts the
 * connection of its blocking wait at once ([InterruptibleWait]). A value taken from Redis but not
 * handed out when an interrupt ends a take stays for the next one (buffered, or read back from
 * the processing list after the aborted connection).
 *
 * A take moves what is ready in one round trip: a batch of values with the step script, or,
 * while the list carries frames of many values, two frames with plain pipelined `LMOVE`s
 * ([takeEntries]), which Redis serves for about half the script's cost.
 *
 * While Redis is unreachable: [take] waits for it; [take] with a timeout gives up at its
 * deadline (connecting and every socket wait are bounded by it, but each reply gets at least
 * [RedisConnections.LEAST_ANSWER_MS], a slow link's round trip) with [RedisUnavailableException]. A timed take
 * starts no round trip past its deadline, and asks Redis to end its blocking wait the take's last
 * round trip before the deadline, so that over a slow link the reply comes by it (or, when less
 * than a round trip is left, waits the rest here and returns empty: nothing published from then
 * on could come back in time). A timed take whose blocking wait was answered too late (past
 * the deadline plus [RedisConnections.BLOCKING_DEADLINE_GRACE_MS]: a loaded machine, or a connection that
 * froze during the wait) returns empty, as for any value that did not come in time: Redis
 * answered the take's step, and the wait's own reply was due only at the deadline; the dropped
 * connection is recovered by the next take, which delivers a value moved meanwhile. [poll] and [drain] never wait for a reconnect: they replace a
 * broken connection once, at once, and throw [RedisUnavailableException] once Redis did not
 * answer within [NO_WAIT_BOUND_MS] (plus [RedisConnections.DEADLINE_GRACE_MS] on a frozen socket).
 *
 * [close] leaves the source's reader set and deletes the reader's lists; it does not wait for a
 * blocked read (it closes that read's connection instead), and waits at most [CLOSE_BOUND_MS]
 * for an unreachable Redis (then the lists stay, with a WARN, until the core closes).
 */
internal class OptimusReader<T>(
    private val core: OptimusCore,
    private val source: SourceKeys,
    val list: ByteArray,
) : Reader<T> {
    private val processing = core.keys.processingOf(list)
    private val missedKey = core.keys.missedOf(list)
    private val session = RedisSession(core.connections)
    // entries of the processing list (a frame or a single value) with envelopes not handed out yet
    private val buffer = ArrayDeque<BufferedEntry>()
    private var delivered = 0 // entries at the head of the processing list, wholly handed out, not yet acknowledged
    private var recovering = false
    private var framed = false // whether the last entries taken were frames of many values (see takeEntries)
    // as many ids as the source retains (at least the default): a registration after the reader's lease lapsed copies the
    // whole retained log into its list again, and every value of it this reader handed out is then skipped
    private val recent = RecentIds(maxOf(RecentIds.DEFAULT_CAPACITY, source.retention))
    private val held = core.holdCodec() // the turn's, as the buffer is: values decode with it, no pool operation each
    private val backoff = Backoff()
    private val closed = AtomicBoolean()
    private val closing = CountDownLatch(1) // ends a take's pause (a backoff, a deadline's last moment) at close()
    private val turn = ReentrantLock() // one call of this reader at a time: the buffer and the session are the turn's
    // set while a take holds the turn and waits for a value to be published, or for Redis to come back
    @Volatile private var takeWaits: Wait? = null
    @Volatile private var lastFailure: Exception? = null // why Redis was unreachable, while takeWaits is Wait.REDIS

    private enum class Wait { VALUE, REDIS }

    /** Whether a call of this reader has the turn now (for tests). */
    internal val isTurnHeld: Boolean get() = turn.isLocked

    @Throws(InterruptedException::class)
    override fun take(): T = inTurn { next(wait = true, deadline = null)!! }

    @Throws(InterruptedException::class)
    override fun take(timeout: Duration?): Optional<T> {
        java.util.Objects.requireNonNull(timeout, "timeout must not be null")
        val nanos = if (timeout!!.isNegative) 0 else boundedNanos(timeout)
        return inTurn {
            if (nanos == 0L) present(next(wait = false, deadline = null))
            else present(next(wait = true, deadline = System.nanoTime() + nanos))
        }
    }

    override fun poll(): Optional<T> = inTurnUnlessATakeWaits({ present(null) }) { present(next(wait = false, deadline = null)) }

    @Suppress("UNCHECKED_CAST")
    private fun present(value: T?): Optional<T> = Optional.ofNullable(value) as Optional<T>

    /**
     * Every value available now. A failure after some values were handed out (Redis unreachable
     * when the reader goes back to it for more) returns those values: they count as delivered
     * already, so throwing would lose them. The failure comes again at the next read if it lasts.
     */
    override fun drain(): List<T> = inTurnUnlessATakeWaits({ ArrayList<T>() }) {
        val values = ArrayList<T>()
        while (true) {
            val value = try {
                next(wait = false, deadline = null)
            } catch (e: RuntimeException) {
                if (values.isEmpty()) throw e
                null
            }
            values += value ?: break
        }
        values
    }

    /**
     * Read on a pooled session, not in this reader's turn: a take of another thread may hold the
     * turn for as long as it waits for a value, and the count is Redis's, kept by the scripts.
     */
    override fun missed(): Long {
        checkUsable()
        val what = "reading the missed count of a reader of source '${source.name}'"
        return core.interruptibleInOutage({ what }, waitedFor = OptimusCore.WAITED_FOR_ANSWER, abortsWaitsForAnswers = true, flagSetBeforeEnds = false) {
            core.withSession(what) { pooled ->
                pooled.retryingUntil(System.nanoTime() + NO_WAIT_BOUND_MS * 1_000_000, what) { it.get(missedKey) }
            }
        }?.let { String(it).toLong() } ?: 0L
    }

    override fun close() {
        if (!closed.compareAndSet(false, true)) return
        closing.countDown() // wakes a take pausing between round trips
        session.abort() // wakes a read blocked on it
        // the codec's session goes back to its pool unless a call still has the turn (then it is left to the collector)
        if (turn.tryLock()) {
            try {
                held?.close()
            } finally {
                turn.unlock()
            }
        }
        core.forgetReader(list)
        if (core.connections.isClosed) return // the core's close removed its readers
        try {
            RedisSession(core.connections).use { cleanup ->
                cleanup.retryingUntil(System.nanoTime() + CLOSE_BOUND_MS * 1_000_000, "closing a reader") { jedis ->
                    val pipeline = jedis.pipelined()
                    queueReaderRemoval(pipeline, core.keys, source, list)
                    core.disownReader(pipeline, list)
                    pipeline.sync()
                }
            }
        } catch (e: RuntimeException) {
            LOG.warn(
                "a reader of core '{}' could not remove its Redis lists ({}); they stay until the core closes or its lease lapses",
                core.name(),
                e.toString(),
            )
        }
    }

    private inline fun <R> inTurn(action: () -> R): R {
        turn.lock()
        try {
            return action()
        } finally {
            turn.unlock()
        }
    }

    /**
     * For [poll] and [drain], which never wait for a value nor for a reconnect (the Reader
     * contract, also for a reader shared by threads): [action] in this reader's turn, after any
     * other call's round trip; but while a take of another thread holds the turn to wait for a
     * value, [none] at once (the take waits because there was none; a value published now goes
     * to it), and while it waits for Redis to come back, [RedisUnavailableException] at once.
     */
    private inline fun <R> inTurnUnlessATakeWaits(none: () -> R, action: () -> R): R {
        val started = System.nanoTime()
        when (takeTurnUnlessATakeWaits()) {
            Wait.VALUE -> {
                checkUsable()
                return none()
            }
            Wait.REDIS -> {
                checkUsable()
                val why = lastFailure ?: IllegalStateException("Redis did not answer a take of this reader")
                throw RedisSession.unavailable("reading a value of an Optimus source of core '${core.name()}'", started, why)
            }
            null -> {}
        }
        try {
            return action()
        } finally {
            turn.unlock()
        }
    }

    /**
     * Takes the turn (`null`), or returns what the take of another thread that holds it waits for
     * (the turn not taken). While another call does a round trip it waits in the lock's queue, so
     * it has the turn as soon as that call ends, and looks again every [TURN_LOOK_NANOS] in case a
     * take starts to wait. [poll] and [drain] throw no [InterruptedException]: an interrupt is
     * kept for the caller (set again on return), not waited on.
     */
    private fun takeTurnUnlessATakeWaits(): Wait? {
        if (turn.tryLock()) return null
        var interrupted = false
        try {
            while (true) {
                takeWaits?.let { return it }
                try {
                    if (turn.tryLock(TURN_LOOK_NANOS, TimeUnit.NANOSECONDS)) return null
                } catch (_: InterruptedException) {
                    interrupted = true
                }
            }
        } finally {
            if (interrupted) Thread.currentThread().interrupt()
        }
    }

    /** Runs [pause] (a wait of a take that holds the turn), telling [poll] and [drain] what it waits for. */
    private inline fun <R> waitingFor(what: Wait, pause: () -> R): R {
        takeWaits = what
        try {
            return pause()
        } finally {
            takeWaits = null
        }
    }

    private fun checkUsable() {
        failIfClosed("")
        core.checkOpen()
        core.checkStarted("reading an Optimus source")
    }

    /** After [close]: releases the connection (a read may have opened one meanwhile) and throws. */
    private fun failIfClosed(moment: String) {
        if (!closed.get()) return
        session.close()
        throw IllegalStateException(
            "reader closed: this reader of an Optimus source was closed by Reader.close()$moment; take a new reader",
        )
    }

    /**
     * The next value. [wait]: block until [deadline] (a nanoTime; `null`: forever) for one;
     * else return `null` at once if there is none.
     */
    private fun next(wait: Boolean, deadline: Long?): T? = core.explainingRefusals("reading a source") { nextValue(wait, deadline) }

    @Suppress("UNCHECKED_CAST")
    private fun nextValue(wait: Boolean, deadline: Long?): T? {
        val started = System.nanoTime()
        // how long Redis may be unreachable before this read gives up (null: never)
        val redisDeadline = if (wait) deadline else started + NO_WAIT_BOUND_MS * 1_000_000
        // a timed take gives each reply at least LEAST_ANSWER_MS (a slow link's round trip) and starts none past its deadline
        val timed = wait && deadline != null
        val answerMillis = if (timed) RedisConnections.LEAST_ANSWER_MS else 0L
        var roundTrips = 0
        var failed: Exception? = null // the last failure, if no round trip succeeded since
        var failures = 0
        while (true) {
            checkUsable()
            // a value already taken, or one Redis holds for this reader, is handed out whatever the
            // interrupt flag (the Reader contract: only a take that waits ends with
            // InterruptedException); the flag is checked before each wait, the blocking move's and
            // every pause's, and a value buffered when it ends a take stays for the next one
            deliver()?.let { return it as T }
            if (timed && roundTrips > 0 && deadline!! - System.nanoTime() <= 0) {
                if (failed != null) throw RedisSession.unavailable("reading a value of an Optimus source of core '${core.name()}'", started, failed)
                return null
            }
            try {
                roundTrips++
                if (recovering) {
                    recover(redisDeadline, answerMillis)
                    failed = null
                    continue
                }
                val stepStarted = System.nanoTime()
                val taken = session.once(redisDeadline, 0, answerMillis) {
                    // frames of many values: a plain pipelined take; many small entries: the script's, up to a batch of values
                    if (framed) takeEntries(it, processing, list, delivered, FRAMES_PER_TAKE)
                    else StepBatch(processing, list, null).run(it, ack = delivered, take = StageService.BATCH)
                }
                val roundTrip = System.nanoTime() - stepStarted
                failed = null
                backoff.reset() // Redis answered: a later outage starts from the shortest wait again
                delivered = 0
                if (taken.isNotEmpty()) {
                    framed = taken.sumOf(Frame::count) >= FRAMED_VALUES * taken.size
                    taken.forEach(::buffer)
                    continue
                }
                if (!wait) return null
                if (deadline != null && deadline - System.nanoTime() <= 0) return null
                if (Thread.interrupted()) throw InterruptedException("interrupted while waiting for a value of an Optimus source")
                // Redis's reply comes about a round trip after its wait ends: end the wait that much before the deadline
                val serverDeadline = deadline?.let { it - roundTrip }
                if (deadline != null && serverDeadline!! - System.nanoTime() <= 0) {
                    // a value published from now on could not come back by the deadline
                    waitingFor(Wait.VALUE) { core.connections.pauseInterruptibly(ceilMillis(deadline - System.nanoTime()), closing) }
                    checkUsable()
                    return null
                }
                val moved = try {
                    waitingFor(Wait.VALUE) {
                        InterruptibleWait(session).run { session.blockingMove(deadline, list, processing, serverDeadline, answerMillis) }
                    }
                } catch (_: ClosedByInterruptException) {
                    // the wait was cut off: a value Redis moved meanwhile is in the processing list
                    recovering = true
                    Thread.interrupted()
                    throw InterruptedException("interrupted while waiting for a value of an Optimus source")
                } catch (_: LateReply) {
                    // Redis answered (if at all) after the deadline: nothing came in time; a value
                    // it moved meanwhile is in the processing list, for the next take
                    recovering = true
                    return null
                }
                moved?.let {
                    framed = Frame.count(it) >= FRAMED_VALUES
                    buffer(it)
                }
            } catch (e: InterruptedException) {
                throw e
            } catch (e: Exception) {
                failIfClosed(" while it waited")
                if (core.connections.isClosed) throw CoreClosedException(core.name()).apply { initCause(e) }
                if (!RedisConnections.isTransient(e)) throw e
                failed = e
                recovering = true
                failures++
                val left = redisDeadline?.let { it - System.nanoTime() }
                // without waiting, a broken connection is replaced once, at once; no waiting for a reconnect
                if ((left != null && left <= 0) || (!wait && failures > 1)) {
                    throw RedisSession.unavailable("reading a value of an Optimus source of core '${core.name()}'", started, e)
                }
                if (wait) {
                    lastFailure = e
                    waitingFor(Wait.REDIS) {
                        core.connections.pauseInterruptibly(backoff.next().let { if (left == null) it else minOf(it, ceilMillis(left)) }, closing)
                    }
                }
            }
        }
    }

    /**
     * A taken entry (a frame, or a single envelope) and where its envelopes lie in it ([Frame.envelopeBounds]):
     * they are read in place, never copied out; [next] is the first not handed out yet.
     */
    private class BufferedEntry(val bytes: ByteArray, val bounds: IntArray) {
        var next = 0
        val isHandedOut: Boolean get() = 2 * next == bounds.size
    }

    /** Buffers [entry]; an entry it cannot read counts as handed out at once (skipped, with a warning). */
    private fun buffer(entry: ByteArray) {
        val bounds = try {
            Frame.envelopeBounds(entry)
        } catch (e: CodecException) {
            LOG.warn("a reader of core '{}' skipped an entry it cannot decode: {}", core.name(), e.message)
            IntArray(0)
        }
        buffer.addLast(BufferedEntry(entry, bounds))
    }

    /**
     * Hands out the next buffered value, skipping duplicates and undecodable envelopes. An entry
     * counts as delivered (acknowledged by the next step) once all its values were handed out:
     * a frame is acknowledged as a whole.
     *
     * A value the codec fails on is skipped with a WARN naming its id, whatever the codec threw:
     * a codec of the user's may throw another exception than [CodecException] (against its
     * contract), and the value, counted as handed out, would otherwise be lost without a word
     * (a [drain] that had values keeps them and drops the failure).
     */
    private fun deliver(): Any? {
        while (true) {
            val entry = buffer.firstOrNull() ?: return null
            if (entry.isHandedOut) {
                buffer.removeFirst()
                delivered++
                continue
            }
            val at = 2 * entry.next++
            var id: Long? = null // known once the envelope is parsed, for the warning
            try {
                val envelope = Envelope.parse(entry.bytes, entry.bounds[at], entry.bounds[at + 1])
                id = envelope.id
                if (envelope.id in recent) continue
                recent.add(envelope.id)
                val value = envelope.value(core, held) ?: continue
                if (entry.isHandedOut) {
                    buffer.removeFirst() // the last value of its entry: the entry is delivered with it
                    delivered++
                }
                return value
            } catch (e: VirtualMachineError) {
                throw e
            } catch (e: Throwable) {
                // a CodecException, or anything a codec that broke its contract throws: the value is skipped
                core.readerSkips.record(
                    "a reader of source '${source.name}' of core '${core.name()}' skipped values",
                    1,
                    "codec ${core.codec}: $e",
                ) {
                    LOG.warn(
                        "a reader of source '{}' of core '{}' skipped a value{} it cannot decode with codec {}: {} (further " +
                            "ones are counted, at most one line per {} s)",
                        source.name, core.name(), if (id == null) "" else " (value id $id)", core.codec, e.toString(),
                        RateLimitedLog.DEFAULT_SECONDS,
                    )
                }
            }
        }
    }

    /** After a lost connection: the processing list is the truth; skip what was handed out. */
    private fun recover(deadline: Long?, answerMillis: Long) {
        val entries = session.once(deadline, 0, answerMillis) { it.lrange(processing, 0, -1) }
        buffer.clear()
        delivered = 0
        for (raw in entries) {
            // leading entries whose values were all handed out are acknowledged with the next step
            if (buffer.isEmpty() && allHandedOut(raw)) delivered++ else buffer(raw)
        }
        recovering = false
    }

    private fun allHandedOut(entry: ByteArray): Boolean = try {
        val bounds = Frame.envelopeBounds(entry)
        (0 until bounds.size / 2).all { k -> Envelope.parse(entry, bounds[2 * k], bounds[2 * k + 1]).id in recent }
    } catch (_: CodecException) {
        false
    }

    private companion object {
        /** The most [poll], [drain] and [missed] wait for Redis to answer. */
        const val NO_WAIT_BOUND_MS = 500L
        const val CLOSE_BOUND_MS = 2000L

        /** How long a [poll] or [drain] waits for a turn another call holds before it looks again at what that call waits for. */
        const val TURN_LOOK_NANOS = 1_000_000L

        /** Entries whose values average at least this many are taken by [takeEntries], [FRAMES_PER_TAKE] at a time. */
        const val FRAMED_VALUES = 64

        /** Frames one plain take moves (up to 512 values when frames are full; at most 2 MiB unless a frame holds one big value). */
        const val FRAMES_PER_TAKE = 2
        val LOG = LoggerFactory.getLogger(OptimusReader::class.java)
    }
}

/**
 * Queues the removal of reader [list] of [source] from Redis: first from the source's reader set
 * (no publish writes to it after that), then its list, processing list and missed counter.
 */
internal fun queueReaderRemoval(pipeline: redis.clients.jedis.Pipeline, keys: Keys, source: SourceKeys, list: ByteArray) {
    pipeline.srem(source.readers, list)
    pipeline.del(list, keys.processingOf(list), keys.missedOf(list))
}

package dev.prime.optimus

import dev.prime.CoreClosedException
import dev.prime.Reader
import org.slf4j.LoggerFactory
import redis.clients.jedis.args.ListDirection
import java.time.Duration
import java.util.Optional

/**
 * A reader of an [OptimusSource]: its own Redis list, which the source fills and trims to the
 * retention (counting what it trims in a `:missed` counter).
 *
 * Design note. A taken value is first moved to the reader's processing list and removed from it
 * only with the next operation, so a connection lost between Redis sending a value and this
 * reader receiving it loses nothing: after reconnecting the reader reads its processing list
 * again and skips, by id, what it had already handed out. All methods synchronise on the reader
 * (the [Reader] contract allows concurrent calls); a blocked [take] is woken by closing the
 * core, which closes its connection.
 */
internal class OptimusReader<T>(
    private val core: OptimusCore,
    val list: ByteArray,
) : Reader<T> {
    private val processing = core.keys.processingOf(list)
    private val missedKey = core.keys.missedOf(list)
    private val session = RedisSession(core.connections)
    private val buffer = ArrayDeque<ByteArray>() // in the processing list, not handed out yet
    private var delivered = 0 // at the head of the processing list, handed out, not yet acknowledged
    private var recovering = false
    private val recent = RecentIds()
    private val backoff = Backoff()

    override fun take(): T = synchronized(this) { next(Long.MAX_VALUE)!! }

    override fun take(timeout: Duration?): Optional<T> {
        java.util.Objects.requireNonNull(timeout, "timeout must not be null")
        val nanos = if (timeout!!.isNegative) 0 else timeout.toNanos()
        return synchronized(this) {
            present(next(if (nanos == 0L) null else System.nanoTime() + nanos))
        }
    }

    override fun poll(): Optional<T> = synchronized(this) { present(next(null)) }

    @Suppress("UNCHECKED_CAST")
    private fun present(value: T?): Optional<T> = Optional.ofNullable(value) as Optional<T>

    override fun drain(): List<T> = synchronized(this) {
        val values = ArrayList<T>()
        while (true) {
            values += next(null) ?: break
        }
        values
    }

    override fun missed(): Long = synchronized(this) {
        core.checkOpen()
        session.retrying { it.get(missedKey) }?.let { String(it).toLong() } ?: 0L
    }

    /** The next value; waits until [deadline] (a nanoTime; null: do not wait). */
    @Suppress("UNCHECKED_CAST")
    private fun next(deadline: Long?): T? {
        while (true) {
            core.checkOpen()
            if (deadline != null && Thread.interrupted()) throw InterruptedException("interrupted while waiting for a value")
            deliver()?.let { return it as T }
            try {
                if (recovering) {
                    recover()
                    continue
                }
                val taken = session.once { StepBatch(processing, list, null).run(it, ack = delivered, take = StageService.BATCH) }
                delivered = 0
                if (taken.isNotEmpty()) {
                    buffer.addAll(taken)
                    continue
                }
                if (deadline == null) return null
                val remaining = deadline - System.nanoTime()
                if (remaining <= 0) return null
                val seconds = (remaining / 1e9).coerceIn(MIN_WAIT_SECONDS, RedisConnections.POLL_SECONDS)
                session.once { it.blmove(list, processing, ListDirection.LEFT, ListDirection.RIGHT, seconds) }
                    ?.let(buffer::add)
                backoff.reset()
            } catch (e: Exception) {
                if (core.connections.isClosed) throw CoreClosedException(core.name()).apply { initCause(e) }
                if (!RedisConnections.isTransient(e)) throw e
                recovering = true
                core.connections.pause(backoff.next())
            }
        }
    }

    /** Hands out the next buffered value, skipping duplicates and undecodable entries. */
    private fun deliver(): Any? {
        while (buffer.isNotEmpty()) {
            val raw = buffer.removeFirst()
            delivered++
            try {
                val envelope = Envelope.parse(raw)
                if (envelope.id in recent) continue
                recent.add(envelope.id)
                val value = envelope.payload()?.let(core.codec::decode) ?: continue
                return value
            } catch (e: CodecException) {
                LOG.warn("a reader of core '{}' skipped a value it cannot decode: {}", core.name(), e.message)
            }
        }
        return null
    }

    /** After a lost connection: the processing list is the truth; skip what was handed out. */
    private fun recover() {
        val entries = session.once { it.lrange(processing, 0, -1) }
        buffer.clear()
        delivered = 0
        for (raw in entries) {
            val id = try {
                Envelope.parse(raw).id
            } catch (_: CodecException) {
                null
            }
            if (buffer.isEmpty() && id != null && id in recent) delivered++ else buffer.add(raw)
        }
        recovering = false
    }

    private companion object {
        const val MIN_WAIT_SECONDS = 0.001
        val LOG = LoggerFactory.getLogger(OptimusReader::class.java)
    }
}

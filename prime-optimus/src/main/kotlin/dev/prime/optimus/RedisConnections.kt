package dev.prime.optimus

import dev.prime.CoreClosedException
import redis.clients.jedis.Jedis
import redis.clients.jedis.exceptions.JedisConnectionException
import redis.clients.jedis.exceptions.JedisDataException
import java.time.Duration
import java.util.concurrent.ConcurrentHashMap
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * Every Redis connection of one core, so that closing the core closes them all: closing a
 * connection is the only way to wake a thread blocked in a socket read (neither an interrupt nor
 * a coroutine cancellation does). Blocking commands ask the server for at most [POLL_SECONDS];
 * the socket of a blocking command gives up after [BLOCKING_SOCKET_TIMEOUT], so a half-open
 * connection is noticed instead of waiting forever.
 */
internal class RedisConnections(
    private val endpoint: RedisEndpoint,
    val coreName: String,
) {
    private val open: MutableSet<Jedis> = ConcurrentHashMap.newKeySet()
    private val closedLatch = CountDownLatch(1)

    @Volatile
    var isClosed: Boolean = false
        private set

    fun open(): Jedis {
        ensureOpen()
        val jedis = endpoint.connect("prime-$coreName", COMMAND_TIMEOUT, BLOCKING_SOCKET_TIMEOUT)
        open.add(jedis)
        if (isClosed) {
            release(jedis)
            ensureOpen()
        }
        return jedis
    }

    fun release(jedis: Jedis) {
        open.remove(jedis)
        try {
            jedis.close()
        } catch (_: RuntimeException) {
            // a broken connection may fail to close cleanly; it is gone either way
        }
    }

    fun ensureOpen() {
        if (isClosed) throw CoreClosedException(coreName)
    }

    /** Waits up to [millis] or until the core closes, whichever comes first. */
    fun pause(millis: Long) {
        try {
            closedLatch.await(millis, TimeUnit.MILLISECONDS)
        } catch (e: InterruptedException) {
            Thread.currentThread().interrupt()
            throw CoreClosedException(coreName).apply { initCause(e) }
        }
    }

    fun closeAll() {
        isClosed = true
        closedLatch.countDown()
        for (jedis in open.toList()) release(jedis)
    }

    companion object {
        const val POLL_SECONDS = 1.0
        val COMMAND_TIMEOUT: Duration = Duration.ofSeconds(10)
        val BLOCKING_SOCKET_TIMEOUT: Duration = Duration.ofSeconds(6)

        /** Whether [e] means "try again on a new connection": the connection broke or the server is still loading. */
        fun isTransient(e: Exception): Boolean =
            e is JedisConnectionException ||
                (e is JedisDataException && (e.message?.startsWith("LOADING") == true || e.message?.startsWith("BUSY") == true))
    }
}

/**
 * One connection of one user (a service, a reader, a caller), opened lazily and replaced when
 * it breaks. Not thread-safe: its user serialises calls.
 */
internal class RedisSession(private val connections: RedisConnections) : AutoCloseable {
    private var jedis: Jedis? = null

    /** Runs [op] once; if the connection broke, drops it (the next call opens a new one) and rethrows. */
    fun <T> once(op: (Jedis) -> T): T {
        val current = jedis ?: connections.open().also { jedis = it }
        try {
            return op(current)
        } catch (e: Exception) {
            if (RedisConnections.isTransient(e)) {
                jedis = null
                connections.release(current)
            }
            throw e
        }
    }

    /**
     * Runs [op], which must be safe to repeat, until it succeeds on some connection; waits
     * between attempts (20 ms doubling to 1 s) while Redis is unreachable.
     *
     * @throws CoreClosedException once the core is closed
     */
    fun <T> retrying(op: (Jedis) -> T): T {
        var backoff: Backoff? = null // made on the first failure only: this is on every call's path
        while (true) {
            connections.ensureOpen()
            try {
                return once(op)
            } catch (e: Exception) {
                if (connections.isClosed) throw CoreClosedException(connections.coreName).apply { initCause(e) }
                if (!RedisConnections.isTransient(e)) throw e
                connections.pause((backoff ?: Backoff().also { backoff = it }).next())
            }
        }
    }

    /**
     * Like [retrying], but gives up at [deadline] (a [System.nanoTime]; `null`: never) with a
     * [RedisUnavailableException] that names [what] (e.g. "publish to source 'imu'") and the last
     * error. The wait between attempts never overshoots the deadline.
     *
     * @throws CoreClosedException once the core is closed
     * @throws RedisUnavailableException when the deadline passes while Redis is unreachable
     */
    fun <T> retryingUntil(deadline: Long?, what: String, op: (Jedis) -> T): T {
        if (deadline == null) return retrying(op)
        val started = System.nanoTime()
        var backoff: Backoff? = null
        while (true) {
            connections.ensureOpen()
            try {
                return once(op)
            } catch (e: Exception) {
                if (connections.isClosed) throw CoreClosedException(connections.coreName).apply { initCause(e) }
                if (!RedisConnections.isTransient(e)) throw e
                val left = deadline - System.nanoTime()
                if (left <= 0) {
                    val waited = Duration.ofNanos(System.nanoTime() - started)
                    throw RedisUnavailableException(
                        "$what gave up after ${waited.toMillis()} ms: Redis is unreachable ($e); check that Redis " +
                            "runs and is reachable from this process",
                        e,
                    )
                }
                val wait = (backoff ?: Backoff().also { backoff = it }).next()
                connections.pause(minOf(wait, ceilMillis(left)))
            }
        }
    }

    override fun close() {
        jedis?.let(connections::release)
        jedis = null
    }
}

/** The waits between attempts to reach Redis: 20 ms, doubling up to 1 s, until [reset]. */
internal class Backoff {
    private var wait = FIRST_MS

    /** The wait before the next attempt; the one after it is twice as long. */
    fun next(): Long = wait.also { wait = (wait * 2).coerceAtMost(MAX_MS) }

    /** Back to the shortest wait, after a success. */
    fun reset() {
        wait = FIRST_MS
    }

    private companion object {
        const val FIRST_MS = 20L
        const val MAX_MS = 1000L
    }
}

/** Nanoseconds to whole milliseconds, rounded up (at least 1). */
private fun ceilMillis(nanos: Long): Long = ((nanos + 999_999) / 1_000_000).coerceAtLeast(1)

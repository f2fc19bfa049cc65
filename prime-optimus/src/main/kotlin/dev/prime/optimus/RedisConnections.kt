package dev.prime.optimus

import dev.prime.CoreClosedException
import org.slf4j.LoggerFactory
import redis.clients.jedis.Jedis
import redis.clients.jedis.Protocol
import redis.clients.jedis.exceptions.JedisConnectionException
import redis.clients.jedis.exceptions.JedisDataException
import redis.clients.jedis.exceptions.JedisRedirectionException
import java.io.IOException
import java.net.Socket
import java.net.SocketTimeoutException
import java.nio.channels.ClosedByInterruptException
import java.time.Duration
import java.util.concurrent.ConcurrentHashMap
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicBoolean

/**
 * Every Redis connection of one core, so that closing the core closes them all: closing a
 * connection is the only way to wake a thread blocked in a socket read (neither an interrupt nor
 * a coroutine cancellation does). That holds for a connection still logging in too ([open] keeps
 * its socket from the moment it is connected), or a thread waiting for a frozen Redis to answer
 * its login would outlast the close by up to its timeout. Blocking commands ask the server for at
 * most [POLL_SECONDS]; the socket of a blocking command gives up after [BLOCKING_SOCKET_TIMEOUT], so a half-open
 * connection is noticed instead of waiting forever. Operations with a deadline (a call, a timed
 * read) bound connecting and every socket wait by that deadline as well ([RedisSession.once]).
 * On a Redis Cluster every connection goes to the master of the topology's slot ([ClusterRoute]);
 * a failed or redirected connection makes the next one look that master up again. With
 * [replicaAcks] every operation is confirmed by that many replicas before it counts as done
 * ([RedisSession.once]).
 */
internal class RedisConnections(
    private val endpoint: RedisTarget,
    val coreName: String,
    /** The replicas that must confirm every operation (`WAIT`); `null`: none. */
    val replicaAcks: ReplicaAcks? = null,
) {
    private val open: MutableSet<Jedis> = ConcurrentHashMap.newKeySet()
    // the sockets of connections still logging in ([open]), which [closeAll] closes too
    private val connecting: MutableSet<Socket> = ConcurrentHashMap.newKeySet()
    private val closedLatch = CountDownLatch(1)
    // the latches of waits that also end on their owner's close (pauseInterruptibly(millis, wake)); closeAll opens them
    private val wakes: MutableSet<CountDownLatch> = ConcurrentHashMap.newKeySet()
    private val readOnlyWarned = AtomicBoolean()

    @Volatile
    var isClosed: Boolean = false
        private set

    /** A new connection; [timeout] bounds connecting, logging in and each later command's reply. */
    fun open(timeout: Duration = COMMAND_TIMEOUT): Jedis {
        ensureOpen()
        var socket: Socket? = null // this connection's, while it logs in (set on this thread)
        val jedis = try {
            endpoint.connect("prime-$coreName", timeout, BLOCKING_SOCKET_TIMEOUT) { connected ->
                socket = connected
                connecting += connected
                if (isClosed) closeQuietly(connected) // closeAll ran meanwhile: it may not have seen it
            }
        } catch (e: RuntimeException) {
            if (isClosed) throw CoreClosedException(coreName).apply { initCause(e) }
            if (isTransient(e)) endpoint.routeFailed()
            if (e is JedisDataException && e.message?.contains(MAX_CLIENTS) == true) throw TooManyClients(endpoint.toString(), e)
            throw e
        } finally {
            socket?.let(connecting::remove)
        }
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

    private fun closeQuietly(socket: Socket) {
        try {
            socket.close()
        } catch (_: IOException) {
            // closed either way
        }
    }

    fun ensureOpen() {
        if (isClosed) throw CoreClosedException(coreName)
    }

    /**
     * Redis answered [e], `READONLY`: on one server (not a cluster, whose route finds the new
     * master) that is a replica. Logs one WARN per core saying so; the caller goes on waiting, as
     * during a failover, where a demoted master answers `READONLY` for a moment.
     */
    fun metReadOnly(e: Exception) {
        if (endpoint !is RedisEndpoint || !readOnlyWarned.compareAndSet(false, true)) return
        LOG.warn(
            "core '{}': the Redis at {} is a read-only replica (it answered: {}): Optimus writes, so give the URL of " +
                "the master (with Sentinel or a managed service, its primary endpoint). Until it accepts writes, " +
                "start() waits and publishes and calls give up at their timeouts, as in an outage; during a failover " +
                "a demoted master answers so for a moment only",
            coreName, endpoint, e.message,
        )
    }

    /** A connection failed or Redis redirected it: the next [open] looks up where the keys are again. */
    fun routeFailed() {
        endpoint.routeFailed()
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

    /** Like [pause], but an interrupt ends it with [InterruptedException] (for waits that honour interrupts). */
    @Throws(InterruptedException::class)
    fun pauseInterruptibly(millis: Long) {
        closedLatch.await(millis, TimeUnit.MILLISECONDS)
    }

    /**
     * Like [pauseInterruptibly], but also ends when [wake] is counted down (a reader's own close).
     * Closing the core counts down every [wake] waited on at that moment, and a wake registered
     * after it sees [isClosed], so neither close is missed.
     */
    @Throws(InterruptedException::class)
    fun pauseInterruptibly(millis: Long, wake: CountDownLatch) {
        wakes += wake
        try {
            if (!isClosed) wake.await(millis, TimeUnit.MILLISECONDS)
        } finally {
            wakes -= wake
        }
    }

    fun closeAll() {
        isClosed = true
        closedLatch.countDown()
        wakes.forEach(CountDownLatch::countDown)
        for (socket in connecting.toList()) closeQuietly(socket)
        for (jedis in open.toList()) release(jedis)
        endpoint.close()
    }

    companion object {
        private val LOG = LoggerFactory.getLogger(RedisConnections::class.java)

        /** What Redis answers a connection over its `maxclients` (then it closes the connection). */
        const val MAX_CLIENTS = "max number of clients reached"

        const val POLL_SECONDS = 1.0
        val COMMAND_TIMEOUT: Duration = Duration.ofSeconds(10)
        val BLOCKING_SOCKET_TIMEOUT: Duration = Duration.ofSeconds(6)

        /** How long past a deadline a socket wait may end (the reply of a command sent just before it). */
        const val DEADLINE_GRACE_MS = 250L

        /**
         * The least time a timed take or a call with a timeout gives each reply of Redis (after
         * Redis's own wait, if it waits), however close its deadline: a slow link's round trip, the
         * "plus about a second" of the Reader contract and of `callTimeout`.
         */
        const val LEAST_ANSWER_MS = 1000L

        /**
         * [DEADLINE_GRACE_MS] for a blocking command asked to wait until the deadline: Redis ends
         * such a wait only on a tick of its event loop (every 100 ms at its default `hz` 10), so
         * its reply comes up to that much after the deadline on an idle machine (measured: 71 ms
         * median, 106 ms p99, 192 ms max at load 4.4 on 2 cores) before any scheduling delay.
         * A reply later still is "nothing in time" for a reader (see [LateReply]), at the cost of
         * a new connection. Bounded so that a wait stays within the "timeout plus about a second"
         * of `Reader.take(Duration)`.
         */
        const val BLOCKING_DEADLINE_GRACE_MS = 400L

        /**
         * Whether [e] means "try again on a new connection": the connection broke, the server is
         * still loading, or (on a Redis Cluster) the command went to a server that no longer holds
         * the topology's slot or the cluster is between masters (redirected, `CLUSTERDOWN`,
         * `TRYAGAIN`, `READONLY`, `MASTERDOWN`), or too few replicas confirmed it ([ReplicaAcks]).
         */
        fun isTransient(e: Exception): Boolean =
            e is JedisConnectionException || e is JedisRedirectionException || e is ReplicaAcksMissing ||
                (e is JedisDataException && TRANSIENT_ERRORS.any { e.message?.startsWith(it) == true })

        /** Whether [e] is Redis's `READONLY`: the server is a replica (or a master being demoted). */
        fun isReadOnly(e: Exception): Boolean = e is JedisDataException && e.message?.startsWith("READONLY") == true

        private val TRANSIENT_ERRORS = listOf("LOADING", "BUSY", "CLUSTERDOWN", "TRYAGAIN", "READONLY", "MASTERDOWN")
    }
}

/**
 * One connection of one user (a service, a reader, a caller), opened lazily and replaced when
 * it breaks. Not thread-safe: its user serialises calls; only [abort] may come from another
 * thread.
 *
 * Design note. The socket timeout is set per operation, and only when it changes (a system
 * call): the usual [RedisConnections.COMMAND_TIMEOUT], or for an operation with a deadline the
 * time left plus [RedisConnections.DEADLINE_GRACE_MS] (for a blocking command,
 * [RedisConnections.BLOCKING_DEADLINE_GRACE_MS]), so that a connection that stopped answering
 * (a frozen network) cannot hold a caller much past its deadline.
 */
internal class RedisSession(private val connections: RedisConnections) : AutoCloseable {
    @Volatile private var jedis: Jedis? = null
    private var socketMillis = 0 // the socket timeout the connection has now

    /** Runs [op] once; if the connection broke, drops it (the next call opens a new one) and rethrows. */
    fun <T> once(op: (Jedis) -> T): T = once(null, 0, op)

    /**
     * Runs [op] once, connecting if needed; every socket wait ends by [deadline] (a
     * [System.nanoTime]; `null`: the usual timeouts), or [serverWaitMillis] plus a margin after
     * the command for a command that makes the server wait that long. If the connection broke,
     * drops it and rethrows. With [RedisConnections.replicaAcks], [op] counts as done only once
     * enough replicas confirmed it; if they do not in time, it fails like a broken connection
     * ([ReplicaAcksMissing]: its effects are on the master, perhaps not on a replica).
     */
    fun <T> once(deadline: Long?, serverWaitMillis: Long, op: (Jedis) -> T): T = attempt(deadline, serverWaitMillis, 0, true, op)

    /**
     * Like [once], but every socket wait lasts at least [leastAnswerMillis] (still at most the
     * usual timeouts), however close [deadline] is: a reply that a slow link brings after the
     * deadline is received instead of taken for a connection that does not answer.
     */
    fun <T> once(deadline: Long?, serverWaitMillis: Long, leastAnswerMillis: Long, op: (Jedis) -> T): T =
        attempt(deadline, serverWaitMillis, leastAnswerMillis, true, op)

    /**
     * Runs [op], which only reads, once, like [once] with the usual timeouts, but never waits for
     * [RedisConnections.replicaAcks]: a read stores nothing a replica could lack.
     */
    fun <T> readOnce(op: (Jedis) -> T): T = attempt(null, 0, 0, false, op)

    private fun <T> attempt(deadline: Long?, serverWaitMillis: Long, leastAnswerMillis: Long, confirmed: Boolean, op: (Jedis) -> T): T {
        val aborts = ABORTS_ON_INTERRUPT.get()
        if (aborts == true && Thread.currentThread().isInterrupted) {
            // the flag was set before this operation began: it ends it as an interrupt during its wait
            // would, before anything is sent (else a frozen Redis would hold it until the socket timeout)
            throw CoreClosedException(connections.coreName).apply { initCause(ClosedByInterruptException()) }
        }
        val limit = socketLimit(deadline, serverWaitMillis, leastAnswerMillis)
        val current = jedis ?: connections.open(Duration.ofMillis(limit.toLong())).also {
            jedis = it
            socketMillis = limit
        }
        try {
            if (socketMillis != limit) {
                current.connection.setSoTimeout(limit)
                socketMillis = limit
            }
            // with `false`, a flag set before the operation began changes nothing: it is sent and waited for
            val result = if (aborts == true || (aborts == false && !Thread.currentThread().isInterrupted)) {
                try {
                    InterruptibleWait(this).run { op(current) }
                } catch (e: ClosedByInterruptException) {
                    // as an interrupted pause between two attempts ends ([RedisConnections.pause])
                    throw CoreClosedException(connections.coreName).apply { initCause(e) }
                }
            } else {
                op(current)
            }
            if (confirmed) connections.replicaAcks?.confirm(current, deadline)
            return result
        } catch (e: Exception) {
            if (RedisConnections.isReadOnly(e)) connections.metReadOnly(e)
            if (RedisConnections.isTransient(e)) {
                drop(current)
                if (e !is ReplicaAcksMissing) connections.routeFailed()
            }
            throw e
        } finally {
            // aborted meanwhile: Jedis may have reconnected the closed connection on its own
            if (jedis !== current) connections.release(current)
        }
    }

    /**
     * `BLMOVE from to LEFT RIGHT`, waiting at most [RedisConnections.POLL_SECONDS] and never past
     * [deadline]; the moved value, or `null` if none came. One attempt, like [once]. If its reply
     * does not come by [deadline] plus [RedisConnections.BLOCKING_DEADLINE_GRACE_MS], it throws
     * [LateReply] (the connection is dropped: Redis may still have moved a value). [serverDeadline]
     * (at most [deadline]) ends Redis's wait sooner, so that its reply, a round trip later, comes
     * by [deadline]; [leastAnswerMillis] as for [once].
     */
    fun blockingMove(
        deadline: Long?,
        from: ByteArray,
        to: ByteArray,
        serverDeadline: Long? = deadline,
        leastAnswerMillis: Long = 0,
    ): ByteArray? {
        val waitMillis = waitMillis(serverDeadline)
        return once(deadline, waitMillis, leastAnswerMillis) { jedis ->
            try {
                // sent as a plain command so that the socket timeout set above applies (Jedis gives
                // its blocking commands a fixed timeout of their own)
                jedis.sendCommand(Protocol.Command.BLMOVE, from, to, LEFT, RIGHT, seconds(waitMillis)) as ByteArray?
            } catch (e: JedisConnectionException) {
                throw if (deadline != null && deadline - System.nanoTime() <= 0 && timedOut(e)) LateReply(e) else e
            }
        }
    }

    /**
     * A call's first attempt, in one write: `DEL reply` (no reply to this call can exist yet),
     * `RPUSH input request`, then `BLMOVE reply reply LEFT RIGHT` waiting as [blockingMove] does;
     * the reply (left in the list: a rotation), or `null` if none came within the wait. Redis runs
     * the wait after the push, on this connection. One attempt, like [once]; a command Redis
     * refused throws its error. Without [wait] only the push (`null`): with
     * [RedisConnections.replicaAcks] the push is confirmed by the replicas before the wait.
     * Redis's wait ends [earlierNanos] before [deadline] (as `serverDeadline` does for
     * [blockingMove]); each socket wait lasts at least [answerMillis] past Redis's wait (see [once]).
     */
    fun pushAndWait(
        deadline: Long?,
        input: ByteArray,
        request: ByteArray,
        reply: ByteArray,
        wait: Boolean = true,
        earlierNanos: Long = 0,
        answerMillis: Long = 0,
    ): ByteArray? {
        // a primitive, not a second deadline: this is on every call's path
        val waitMillis = if (!wait) 0 else if (deadline == null) POLL_MILLIS else waitUntil(deadline - earlierNanos, System.nanoTime())
        return once(deadline, waitMillis, waitMillis + answerMillis) { jedis ->
            val connection = jedis.connection
            // arguments Jedis does not copy: the request is written as it is
            connection.sendCommand(commandOf(Protocol.Command.DEL, reply))
            connection.sendCommand(commandOf(Protocol.Command.RPUSH, input, request))
            if (wait) connection.sendCommand(commandOf(Protocol.Command.BLMOVE, reply, reply, LEFT, RIGHT, seconds(waitMillis)))
            val answers = connection.getMany(if (wait) 3 else 2)
            answers.forEach { if (it is RuntimeException) throw it }
            if (wait) answers[2] as ByteArray? else null
        }
    }

    /**
     * How long a blocking command sent at [now] (a [System.nanoTime]) asks Redis to wait, ending
     * by [deadline]: 10 ms to [RedisConnections.POLL_SECONDS].
     */
    fun waitMillis(deadline: Long?, now: Long = System.nanoTime()): Long = if (deadline == null) POLL_MILLIS else waitUntil(deadline, now)

    private fun waitUntil(deadline: Long, now: Long): Long = ceilMillis(deadline - now).coerceIn(MIN_WAIT_MS, POLL_MILLIS)

    private fun socketLimit(deadline: Long?, serverWaitMillis: Long, leastAnswerMillis: Long): Int {
        val usual = if (serverWaitMillis > 0) {
            serverWaitMillis + RedisConnections.BLOCKING_SOCKET_TIMEOUT.toMillis() - (RedisConnections.POLL_SECONDS * 1000).toLong()
        } else {
            RedisConnections.COMMAND_TIMEOUT.toMillis()
        }
        if (deadline == null) return usual.toInt()
        val grace = if (serverWaitMillis > 0) RedisConnections.BLOCKING_DEADLINE_GRACE_MS else RedisConnections.DEADLINE_GRACE_MS
        val left = ceilMillis(deadline - System.nanoTime()).coerceAtLeast(0) + grace
        return minOf(usual, maxOf(left, serverWaitMillis + grace, leastAnswerMillis)).toInt()
    }

    private fun drop(current: Jedis) {
        if (jedis === current) jedis = null
        connections.release(current)
    }

    /**
     * Closes the connection under a user blocked on it (from any thread): its operation fails as
     * a broken connection would, and the next one opens a new connection.
     */
    fun abort() {
        val current = jedis ?: return
        jedis = null
        connections.release(current)
    }

    /**
     * Runs [op], which must be safe to repeat, until it succeeds on some connection; waits
     * between attempts (20 ms doubling to 1 s) while Redis is unreachable.
     *
     * @throws CoreClosedException once the core is closed
     */
    fun <T> retrying(op: (Jedis) -> T): T = retryUntil(null, "") { once(op) }

    /**
     * Like [retrying], but gives up at [deadline] (a [System.nanoTime]; `null`: never) with a
     * [RedisUnavailableException] that names [what] (e.g. "publish to source 'imu'") and the last
     * error. The wait between attempts never overshoots the deadline, and neither do connecting
     * and socket waits (see [once]): a connection that does not answer ends the attempt in time.
     *
     * @throws CoreClosedException once the core is closed
     * @throws RedisUnavailableException when the deadline passes while Redis is unreachable
     */
    fun <T> retryingUntil(deadline: Long?, what: String, op: (Jedis) -> T): T =
        retryUntil(deadline, what) { once(deadline, 0, op) }

    /**
     * [blockingMove], retried like [retryingUntil]; a [LateReply] is not retried but thrown (the
     * wait's deadline passed: nothing came in time, which is the waiter's to report).
     */
    fun blockingMoveUntil(
        deadline: Long?,
        what: String,
        from: ByteArray,
        to: ByteArray,
        serverDeadline: Long? = deadline,
        leastAnswerMillis: Long = 0,
    ): ByteArray? = retryUntil(deadline, what) { blockingMove(deadline, from, to, serverDeadline, leastAnswerMillis) }

    private inline fun <T> retryUntil(deadline: Long?, what: String, attempt: () -> T): T {
        val started = System.nanoTime()
        var backoff: Backoff? = null // made on the first failure only: this is on every call's path
        while (true) {
            connections.ensureOpen()
            try {
                return attempt()
            } catch (e: Exception) {
                if (connections.isClosed) throw CoreClosedException(connections.coreName).apply { initCause(e) }
                if (e is LateReply) throw e // only a blocking wait past its deadline throws it: nothing came in time
                if (!RedisConnections.isTransient(e)) throw e
                val wait = (backoff ?: Backoff().also { backoff = it }).next()
                if (deadline == null) {
                    connections.pause(wait)
                } else {
                    val left = deadline - System.nanoTime()
                    if (left <= 0) throw unavailable(what, started, e)
                    connections.pause(minOf(wait, ceilMillis(left)))
                }
            }
        }
    }

    override fun close() {
        jedis?.let(connections::release)
        jedis = null
    }

    companion object {
        /**
         * Set on a thread while it makes a declaration or a start that an interrupt ends
         * ([OptimusCore.interruptibleInOutage]): then an interrupt that comes while an operation
         * of a session waits for Redis's answer aborts its connection at once ([InterruptibleWait])
         * and the operation fails with [CoreClosedException], as an interrupted pause between two
         * attempts does; else a frozen Redis would hold the interrupted thread until the socket
         * timeout ([RedisConnections.COMMAND_TIMEOUT]). With `true` (a declaration, a start) a flag
         * already set when an operation begins ends it the same way, before it connects or sends
         * anything; with `false` (a publish, a read of dead letters, a reader's registration or
         * count: what succeeds with the flag set when Redis answers, as on the other media) only an
         * interrupt during the wait does. `null`: neither.
         */
        val ABORTS_ON_INTERRUPT: ThreadLocal<Boolean> = ThreadLocal()

        private const val MIN_WAIT_MS = 10L
        private val POLL_MILLIS = (RedisConnections.POLL_SECONDS * 1000).toLong()

        private val POLL_SECONDS_ARGUMENT = RedisConnections.POLL_SECONDS.toString().toByteArray()

        private fun seconds(millis: Long) =
            if (millis == (RedisConnections.POLL_SECONDS * 1000).toLong()) POLL_SECONDS_ARGUMENT else (millis / 1000.0).toString().toByteArray()

        /** The exception for [what] that gave up at its deadline because Redis was unreachable since [started]. */
        fun unavailable(what: String, started: Long, last: Exception): RedisUnavailableException {
            val waited = Duration.ofNanos(System.nanoTime() - started)
            val why = if (RedisConnections.isReadOnly(last)) {
                "Redis is a read-only replica ($last); give the URL of the master, or wait for a failover to end"
            } else {
                "Redis is unreachable ($last); check that Redis runs and is reachable from this process"
            }
            return RedisUnavailableException("$what gave up after ${waited.toMillis()} ms: $why", last)
        }
    }
}

/**
 * The reply of a blocking wait that Redis was asked to end by its deadline did not come by that
 * deadline plus [RedisConnections.BLOCKING_DEADLINE_GRACE_MS]: Redis answered late (a loaded machine) or
 * the connection froze during the wait. To the waiter that is "nothing came in time", not an
 * outage; the connection is dropped like a broken one (a connection error, so [RedisSession.once]
 * drops it), and a value Redis moved meanwhile is on the server, not lost.
 */
internal class LateReply(cause: JedisConnectionException) :
    JedisConnectionException("no reply by the deadline of a blocking wait (${cause.message})", cause)

/** Whether [e] is a socket read that timed out (not a refused, reset or closed connection). */
private fun timedOut(e: Throwable): Boolean {
    var cause: Throwable? = e
    repeat(4) {
        if (cause is SocketTimeoutException) return true
        cause = cause?.cause ?: return false
    }
    return false
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
internal fun ceilMillis(nanos: Long): Long = ((nanos + 999_999) / 1_000_000).coerceAtLeast(1)

/**
 * Redis refused a new connection: it has `maxclients` clients connected. Still a
 * [JedisDataException], so it is handled as Redis's own answer was (it fails the operation, it is
 * not waited out); only its message says what to do.
 */
internal class TooManyClients(redis: String, cause: JedisDataException) : JedisDataException(
    "the Redis at $redis refused a new connection: it has its maxclients clients connected (Redis said: " +
        "${cause.message}). Each core opens a few connections (a heartbeat, one per hosted service, per calling " +
        "thread, per reader and per publishing thread): raise maxclients (CONFIG SET maxclients <n>, or the " +
        "managed service's parameter) or close clients that need not be connected (CLIENT LIST shows them)",
    cause,
)

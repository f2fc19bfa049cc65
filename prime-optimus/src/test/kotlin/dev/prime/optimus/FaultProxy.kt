package dev.prime.optimus

import java.io.IOException
import java.net.InetAddress
import java.net.ServerSocket
import java.net.Socket
import java.net.URI
import java.util.concurrent.ConcurrentHashMap
import java.util.concurrent.atomic.AtomicInteger
import java.util.concurrent.locks.LockSupport

/**
 * A TCP proxy in front of a Redis that injects network faults on command:
 * - [cutAfterWritesContaining]: after forwarding a client write that contains a marker to Redis,
 *   it waits for Redis's answer (so the request surely ran), drops it and closes the connection
 *   (every other such write, so a retry gets through): a connection that broke after the request
 *   reached Redis.
 * - [freeze]: stops forwarding in both directions and leaves every socket open (new connections
 *   are accepted and then left silent): a network that drops everything, as a pulled cable.
 * - [refuse]: closes every connection and each new one, until [restore]: a Redis that is down
 *   (every attempt fails at once, where a frozen one waits for its timeout).
 * - [replyDelayNanos]: holds every chunk of a reply back that long: a slow network, for the
 *   awkward (slow-Redis) variant of the conformance kit.
 * - [switchTo]: points new connections at another Redis and closes every open one: the primary
 *   endpoint of a managed service or of a Sentinel set-up after a failover (its name now resolves
 *   to the promoted replica, and the connections to the old master are gone).
 *
 * Two daemon threads per connection pump the bytes; [close] closes every socket, which ends them.
 * In this module's test-jar, so other modules' tests can run on a slow Redis too.
 */
class FaultProxy @JvmOverloads constructor(target: String, replyDelayNanos: Long = 0) : AutoCloseable {
    /** How long each chunk of a reply is held back from now on (see the class note). */
    @Volatile var replyDelayNanos: Long = replyDelayNanos

    @Volatile private var targetUri = URI(target)
    private val server = ServerSocket(0, 50, InetAddress.getLoopbackAddress())
    private val sockets: MutableSet<Socket> = ConcurrentHashMap.newKeySet()
    private val lock = Object()
    private var frozen = false // guarded by lock
    @Volatile private var marker: ByteArray? = null
    @Volatile private var refusing = false
    private val markedWrites = AtomicInteger()

    /** How many connections were cut after forwarding a marked write. */
    val cuts = AtomicInteger()

    /** How many new connections the proxy closed at once while it [refuse]d. */
    val turnedAway = AtomicInteger()

    /** How many connections the Redis behind the proxy refused (it was down): each was closed at once. */
    val refusedConnects = AtomicInteger()

    val url: String get() = "redis://127.0.0.1:${server.localPort}"

    init {
        daemon("fault-proxy-accept") {
            while (!server.isClosed) {
                val client = try {
                    server.accept()
                } catch (_: IOException) {
                    return@daemon
                }
                if (refusing) {
                    turnedAway.incrementAndGet()
                    client.close()
                    continue
                }
                client.tcpNoDelay = true // as Redis and Jedis do: no write waits for the last one's ACK
                sockets += client
                daemon("fault-proxy-connect") {
                    awaitThaw()
                    val target = targetUri
                    val upstream = try {
                        Socket(target.host, target.port).apply { tcpNoDelay = true }
                    } catch (_: IOException) {
                        refusedConnects.incrementAndGet()
                        client.close()
                        return@daemon
                    }
                    sockets += upstream
                    val link = Link()
                    daemon("fault-proxy-up") { pump(client, upstream, link, upward = true) }
                    pump(upstream, client, link, upward = false)
                }
            }
        }
    }

    /** Cuts the connection after forwarding every other client write that contains [text]. */
    fun cutAfterWritesContaining(text: String) {
        marker = text.toByteArray()
    }

    /** Closes every connection, and each new one at once, until [restore]: a Redis that is down. */
    fun refuse() {
        refusing = true
        sockets.forEach { it.close() }
    }

    /** Connects new connections to Redis again, after [refuse]. */
    fun restore() {
        refusing = false
    }

    /**
     * Connects every new connection to the Redis at [target] (a `redis://host:port` URL) from now
     * on, and closes every open connection, as the primary endpoint of a failed-over Redis does.
     *
     * @throws IllegalArgumentException if [target] has no host or port
     */
    fun switchTo(target: String) {
        val uri = URI(target)
        require(uri.host != null && uri.port > 0) { "give the Redis to switch to as redis://host:port, was '$target'" }
        targetUri = uri
        sockets.forEach { it.close() }
    }

    /** Stops forwarding; connections stay open and silent until [thaw]. */
    fun freeze() = synchronized(lock) { frozen = true }

    /** Forwards again. */
    fun thaw() = synchronized(lock) {
        frozen = false
        lock.notifyAll()
    }

    private fun awaitThaw() = synchronized(lock) {
        while (frozen && !server.isClosed) lock.wait(100)
    }

    /** One proxied connection: whether its next answer from Redis is dropped and the connection cut. */
    private class Link {
        @Volatile var doomed = false
    }

    private fun pump(from: Socket, to: Socket, link: Link, upward: Boolean) {
        val buffer = ByteArray(64 * 1024)
        var tail = ByteArray(0) // the end of the previous chunk: a marker may span two reads
        try {
            while (true) {
                val n = from.getInputStream().read(buffer)
                if (n < 0) break
                awaitThaw()
                val delay = replyDelayNanos
                if (!upward && delay > 0) LockSupport.parkNanos(delay)
                if (!upward && link.doomed) {
                    cuts.incrementAndGet() // Redis answered the marked write: it ran; the client never learns
                    break
                }
                val wanted = marker
                if (upward && wanted != null) {
                    val window = tail + buffer.copyOf(n)
                    tail = window.copyOfRange(maxOf(0, window.size - wanted.size + 1), window.size)
                    if (contains(window, window.size, wanted) && markedWrites.incrementAndGet() % 2 == 1) link.doomed = true
                }
                to.getOutputStream().write(buffer, 0, n)
            }
        } catch (_: IOException) {
            // one side closed
        } finally {
            from.close()
            to.close()
        }
    }

    override fun close() {
        server.close()
        thaw()
        sockets.forEach { it.close() }
    }

    private fun daemon(name: String, body: () -> Unit) {
        Thread(body, name).apply { isDaemon = true }.start()
    }

    companion object {
        /** How long the slow-Redis variants hold every chunk of a reply back: half a millisecond. */
        const val SLOW_REPLY_NANOS: Long = 500_000

        private val slowLinks = ConcurrentHashMap<String, FaultProxy>()

        /**
         * The URL of a proxy in front of the Redis at [target] that holds every reply back
         * [SLOW_REPLY_NANOS] (the kit's slow Redis), for tests handed a Redis URL they do not own
         * (a `CoreSetup` of `@PrimeTest`). One proxy per target for the JVM, closed when it ends.
         */
        @JvmStatic
        fun slowLinkTo(target: String): String = slowLinks.computeIfAbsent(target) { url ->
            if (slowLinks.isEmpty()) {
                Runtime.getRuntime().addShutdownHook(Thread({ slowLinks.values.forEach(FaultProxy::close) }, "fault-proxy-close"))
            }
            FaultProxy(url, SLOW_REPLY_NANOS)
        }.url

        private fun contains(buffer: ByteArray, length: Int, wanted: ByteArray): Boolean {
            outer@ for (start in 0..length - wanted.size) {
                for (i in wanted.indices) if (buffer[start + i] != wanted[i]) continue@outer
                return true
            }
            return false
        }
    }
}

package dev.prime.optimus

import java.io.IOException
import java.net.InetAddress
import java.net.ServerSocket
import java.net.Socket
import java.net.URI
import java.util.concurrent.ConcurrentHashMap
import java.util.concurrent.LinkedBlockingQueue
import java.util.concurrent.TimeUnit
import java.util.concurrent.locks.LockSupport

/**
 * A TCP proxy on the loopback interface in front of a Redis that delays every byte [delayNanos]
 * in each direction, as a network link of that latency: a byte read from one side reaches the
 * other [delayNanos] after it was read, so a round trip takes twice the delay longer; bytes read
 * together arrive together, and later bytes are not held back further by earlier ones (latency,
 * no bandwidth limit). Accepting a connection costs no delay (the proxy accepts it itself): only
 * what the client and Redis send each other is late.
 *
 * Per connection two reading and two writing daemon threads; [close] closes every socket, which
 * ends them.
 */
class LatencyProxy(target: String, @Volatile var delayNanos: Long) : AutoCloseable {
    private val targetUri = URI(target)
    private val server = ServerSocket(0, 50, InetAddress.getLoopbackAddress())
    private val sockets: MutableSet<Socket> = ConcurrentHashMap.newKeySet()

    val url: String get() = "redis://127.0.0.1:${server.localPort}"

    init {
        daemon("latency-proxy-accept") {
            while (!server.isClosed) {
                val client = try {
                    server.accept()
                } catch (_: IOException) {
                    return@daemon
                }
                client.tcpNoDelay = true
                sockets += client
                val upstream = try {
                    Socket(targetUri.host, targetUri.port).apply { tcpNoDelay = true }
                } catch (_: IOException) {
                    client.close()
                    continue
                }
                sockets += upstream
                forward(client, upstream)
                forward(upstream, client)
            }
        }
    }

    /** Reads [from] and writes each chunk to [to] once it is due. */
    private fun forward(from: Socket, to: Socket) {
        val chunks = LinkedBlockingQueue<Pair<Long, ByteArray>>() // (due nanoTime, bytes); empty bytes: the end
        daemon("latency-proxy-read") {
            val buffer = ByteArray(64 * 1024)
            try {
                val input = from.getInputStream()
                while (true) {
                    val n = input.read(buffer)
                    if (n < 0) break
                    chunks.put(System.nanoTime() + delayNanos to buffer.copyOf(n))
                }
            } catch (_: IOException) {
                // the socket closed
            }
            chunks.put(System.nanoTime() + delayNanos to ByteArray(0))
        }
        daemon("latency-proxy-write") {
            try {
                val output = to.getOutputStream()
                while (true) {
                    val (due, bytes) = chunks.poll(1, TimeUnit.HOURS) ?: break
                    while (true) {
                        val left = due - System.nanoTime()
                        if (left <= 0) break
                        LockSupport.parkNanos(left)
                    }
                    if (bytes.isEmpty()) break
                    output.write(bytes)
                    output.flush()
                }
            } catch (_: IOException) {
                // the socket closed
            }
            from.close()
            to.close()
        }
    }

    override fun close() {
        server.close()
        sockets.forEach { it.close() }
    }

    private fun daemon(name: String, body: () -> Unit) {
        Thread({
            try {
                body()
            } catch (_: IOException) {
                // closed
            }
        }, name).apply { isDaemon = true }.start()
    }
}

package dev.prime.optimus

import java.io.IOException
import java.net.InetAddress
import java.net.ServerSocket
import java.net.Socket
import java.net.URI
import java.util.concurrent.ConcurrentHashMap
import java.util.concurrent.locks.LockSupport

/**
 * A TCP proxy in front of a Redis that holds every chunk of a reply back for [delayNanos]: a
 * slow network, for the awkward variant of the conformance kit. Two daemon threads per
 * connection pump the bytes; [close] closes every socket, which ends them.
 */
internal class SlowProxy(target: String, private val delayNanos: Long) : AutoCloseable {
    private val targetUri = URI(target)
    private val server = ServerSocket(0, 50, InetAddress.getLoopbackAddress())
    private val sockets: MutableSet<Socket> = ConcurrentHashMap.newKeySet()

    val url: String get() = "redis://127.0.0.1:${server.localPort}"

    init {
        daemon("slow-proxy-accept") {
            while (!server.isClosed) {
                val client = try {
                    server.accept()
                } catch (_: IOException) {
                    return@daemon
                }
                val upstream = Socket(targetUri.host, targetUri.port)
                sockets += client
                sockets += upstream
                daemon("slow-proxy-up") { pump(client, upstream, 0) }
                daemon("slow-proxy-down") { pump(upstream, client, delayNanos) }
            }
        }
    }

    private fun pump(from: Socket, to: Socket, delay: Long) {
        val buffer = ByteArray(64 * 1024)
        try {
            while (true) {
                val n = from.getInputStream().read(buffer)
                if (n < 0) break
                if (delay > 0) LockSupport.parkNanos(delay)
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
        sockets.forEach { it.close() }
    }

    private fun daemon(name: String, body: () -> Unit) {
        Thread(body, name).apply { isDaemon = true }.start()
    }
}

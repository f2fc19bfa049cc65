package dev.prime.optimus

import redis.clients.jedis.JedisSocketFactory
import redis.clients.jedis.exceptions.JedisConnectionException
import java.net.Socket
import java.util.concurrent.atomic.AtomicBoolean

/**
 * Opens the socket of one connection once. Jedis opens a closed connection again by itself on
 * its next command, without what the server held for the old one (a `WATCH`, a `MULTI`, a
 * blocked wait) and without logging in again; a write whose first commands went to the old
 * socket and the rest to a new one would run those unguarded (see [RequestStep.storeWatched]). So
 * a connection closed under its user (the core closing, an interrupted wait) fails like a broken
 * one, and its session opens a new connection in its place. [onSocket] gets the socket once it
 * is connected, before Jedis logs in on it ([RedisTarget.connect]).
 */
internal class OneSocket(private val factory: JedisSocketFactory, private val onSocket: (Socket) -> Unit = {}) : JedisSocketFactory {
    private val opened = AtomicBoolean()

    override fun createSocket(): Socket {
        if (!opened.compareAndSet(false, true)) {
            throw JedisConnectionException("the connection was closed; a new one is opened in its place")
        }
        return factory.createSocket().also(onSocket)
    }
}

package dev.prime.optimus

import redis.clients.jedis.Jedis
import java.net.Socket
import java.time.Duration

/**
 * Where the Redis of a core is: one server ([RedisEndpoint], `redis://`) or a Redis Cluster
 * ([RedisClusterEndpoint], `redis-cluster://`), of which a core only ever talks to the master
 * that holds its topology's hash slot ([ClusterRoute]).
 */
internal interface RedisTarget {
    /** The Redis user this target logs in as (`null`: the default user), for messages. */
    val user: String?

    /**
     * Opens a new connection to the server that holds the core's keys. [timeout] bounds
     * connecting, logging in and every command; [blockingTimeout] bounds how long a blocking
     * command may keep the socket silent. [onSocket] gets the connection's socket as soon as it is
     * connected, before logging in, on the calling thread: closing it ends a login that waits for
     * a Redis that does not answer.
     */
    fun connect(clientName: String, timeout: Duration, blockingTimeout: Duration, onSocket: (Socket) -> Unit = {}): Jedis

    /**
     * A connection failed or Redis redirected a command: the next [connect] looks up again which
     * server holds the keys (a Redis Cluster failed over or moved the slot). Nothing for one server.
     */
    fun routeFailed() {}

    /** Releases what the target holds besides the connections it gave out. */
    fun close() {}

    companion object {
        /**
         * The target of [url]: a Redis Cluster for `redis-cluster://` and `rediss-cluster://`
         * (routed to the slot of [keys]), else one server.
         *
         * @throws IllegalArgumentException if the URL is malformed; the message says how to fix it
         */
        fun parse(url: String, keys: Keys): RedisTarget =
            if (RedisClusterEndpoint.isClusterUrl(url)) ClusterRoute(RedisClusterEndpoint.parse(url), keys) else RedisEndpoint.parse(url)
    }
}

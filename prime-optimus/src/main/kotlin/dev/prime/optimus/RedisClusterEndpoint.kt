package dev.prime.optimus

import redis.clients.jedis.HostAndPort
import redis.clients.jedis.Jedis
import redis.clients.jedis.Protocol
import redis.clients.jedis.exceptions.JedisAccessControlException
import redis.clients.jedis.exceptions.JedisConnectionException
import redis.clients.jedis.exceptions.JedisException
import java.io.IOException
import java.net.Socket
import java.time.Duration
import java.util.concurrent.ConcurrentHashMap
import java.util.concurrent.TimeUnit
import java.util.concurrent.locks.ReentrantLock

/**
 * A Redis Cluster and how to log in to its nodes: parsed from
 * `redis-cluster://[user[:password]@]host:port[,host:port...]` or `rediss-cluster://...` (TLS).
 * The listed nodes are seeds: any one that answers tells where the others are. A cluster has
 * database 0 only, so a URL may end in `/0` or nothing. The password is secret as in
 * [RedisEndpoint] (same rules, same redaction).
 */
internal class RedisClusterEndpoint private constructor(
    val seeds: List<HostAndPort>,
    val user: String?,
    /** The password; never put it in a message. */
    val password: String?,
    val tls: Boolean,
) {
    override fun toString(): String {
        val login = when {
            user != null && password != null -> "$user:***@"
            user != null -> "$user@"
            password != null -> ":***@"
            else -> ""
        }
        val nodes = seeds.joinToString(",") { if (':' in it.host) "[${it.host}]:${it.port}" else "${it.host}:${it.port}" }
        return "${if (tls) "rediss-cluster" else "redis-cluster"}://$login$nodes"
    }

    companion object {
        private const val FORM =
            "expected redis-cluster://[user[:password]@]host:port[,host:port...] (rediss-cluster:// for TLS): one or " +
                "more nodes of the cluster, separated by commas"

        /** Whether [url] names a Redis Cluster (`redis-cluster://` or `rediss-cluster://`). */
        fun isClusterUrl(url: String): Boolean {
            val lower = url.lowercase()
            return lower.startsWith("redis-cluster://") || lower.startsWith("rediss-cluster://")
        }

        /** @throws IllegalArgumentException if [url] is malformed; the message never shows the password */
        fun parse(url: String): RedisClusterEndpoint {
            require(isClusterUrl(url)) { "Redis URL '${RedisEndpoint.redact(url)}' is not a cluster URL; $FORM" }
            val schemeEnd = url.indexOf("://")
            val tls = url.substring(0, schemeEnd).lowercase() == "rediss-cluster"
            val rest = url.substring(schemeEnd + 3)
            val at = rest.lastIndexOf('@')
            val (user, password) = if (at >= 0) RedisEndpoint.login(rest.substring(0, at)) else null to null
            val location = rest.substring(at + 1) // host:port[,host:port...][/0], nothing secret
            if (location.any { it == '?' || it == '#' }) {
                throw IllegalArgumentException(
                    "Redis URL '${RedisEndpoint.redact(url)}' has a query or fragment, which Optimus does not read; $FORM",
                )
            }
            val slash = location.indexOf('/')
            val nodes = if (slash < 0) location else location.substring(0, slash)
            val path = if (slash < 0) "" else location.substring(slash + 1)
            if (path.isNotEmpty() && path != "0") {
                throw IllegalArgumentException(
                    "Redis URL '${RedisEndpoint.redact(url)}' has database '$path', but a Redis Cluster has database 0 " +
                        "only: drop the '/$path' (give each topology its own core name instead: the name is its namespace)",
                )
            }
            val seeds = nodes.split(',').map { node ->
                if (node.isBlank()) {
                    throw IllegalArgumentException("Redis URL '${RedisEndpoint.redact(url)}' has an empty node in its list; $FORM")
                }
                RedisEndpoint.hostAndPort(url, node.trim())
            }
            return RedisClusterEndpoint(seeds.distinct(), user, password, tls)
        }
    }
}

/**
 * The way to the master of a Redis Cluster that holds one topology's keys: every key of a
 * topology carries the topology in a hash tag ([Keys]), so all of them are in one hash slot,
 * and every command and script of the core goes to that slot's master on a connection of its
 * own (a core's connections need what a pooled cluster client cannot give: a socket per
 * blocking reader, per-operation timeouts, closing a connection under a blocked reader).
 *
 * Design note. The route asks a node for the slot map (`CLUSTER SLOTS`) at the first [connect]
 * and again after a connection failed or a command was redirected ([routeFailed]: `MOVED`, `ASK`,
 * `CLUSTERDOWN`, `READONLY`, a refused or broken connection), at most once per
 * [RENEW_INTERVAL_MS] and one thread at a time (under [lock]); the others use the master as it
 * is. It asks the nodes the last map named, then the seeds, on connections of its own whose
 * sockets [close] closes: a lookup that waits for a cluster that stopped answering (its nodes
 * frozen) ends with the core's close, instead of holding the closing thread, and any thread that
 * needs the route, for a timeout per node. A renewal that no node answers keeps the master it
 * knew, so the callers wait as in an outage. After a failover the promoted replica is found this
 * way: until the cluster has promoted it, connecting fails (or is redirected) and the callers
 * wait as in an outage.
 */
internal class ClusterRoute(private val cluster: RedisClusterEndpoint, keys: Keys) : RedisTarget {
    /** The hash slot of every key of the topology. */
    val slot: Int = keys.clusterSlot()

    private val lock = ReentrantLock()
    private var known: HostAndPort? = null // guarded by lock: the master the last answered lookup named
    private var learned: List<HostAndPort> = emptyList() // guarded by lock: the nodes the last answered lookup named
    private var renewedAt = 0L // guarded by lock
    @Volatile private var master: HostAndPort? = null // null: look it up at the next connect
    @Volatile private var closed = false

    /** The sockets of lookups under way, which [close] closes. */
    private val lookups: MutableSet<Socket> = ConcurrentHashMap.newKeySet()

    override val user: String? get() = cluster.user

    override fun connect(clientName: String, timeout: Duration, blockingTimeout: Duration, onSocket: (Socket) -> Unit): Jedis {
        val config = RedisEndpoint.clientConfig(cluster.user, cluster.password, cluster.tls, 0, clientName, timeout, blockingTimeout)
        return RedisEndpoint.open(master(timeout), config, onSocket)
    }

    override fun routeFailed() {
        master = null
    }

    /** The master that holds [slot] now (as far as the cluster has told). */
    fun master(timeout: Duration = DISCOVERY_TIMEOUT): HostAndPort {
        master?.let { return it }
        // a lookup under way on another thread is waited for at most [timeout], as a connection
        // would be, whatever the interrupt flag (a caller that gave up withdraws its request with it set)
        if (!lockWithin(timeout)) throw JedisConnectionException("another thread is looking up the master of the Redis Cluster $cluster (waited $timeout)")
        try {
            master?.let { return it }
            if (closed) throw closedRoute()
            val last = known
            val node = if (last != null && System.nanoTime() - renewedAt < RENEW_INTERVAL_MS * 1_000_000) {
                last
            } else {
                lookUp(minOf(timeout, DISCOVERY_TIMEOUT), last)
            }
            renewedAt = System.nanoTime()
            master = node
            return node
        } finally {
            lock.unlock()
        }
    }

    /** Takes [lock], waiting at most [timeout]; an interrupt neither ends the wait nor is lost. */
    private fun lockWithin(timeout: Duration): Boolean {
        val deadline = System.nanoTime() + timeout.toNanos().coerceAtLeast(1)
        var interrupted = Thread.interrupted()
        try {
            while (true) {
                try {
                    return lock.tryLock((deadline - System.nanoTime()).coerceAtLeast(0), TimeUnit.NANOSECONDS)
                } catch (_: InterruptedException) {
                    interrupted = true
                }
            }
        } finally {
            if (interrupted) Thread.currentThread().interrupt()
        }
    }

    /**
     * Asks the nodes for the slot map, one after the other, until one answers; the master of
     * [slot] it names, or [last] if none answers and there is one.
     */
    private fun lookUp(timeout: Duration, last: HostAndPort?): HostAndPort {
        val config = RedisEndpoint.clientConfig(cluster.user, cluster.password, cluster.tls, 0, "prime-discovery", timeout, timeout)
        val failures = ArrayList<String>()
        // the nodes the cluster named, the master it named last (it may be the one that failed) after them, then the seeds
        val candidates = ((learned - setOfNotNull(last)) + listOfNotNull(last) + cluster.seeds).distinct()
        for (node in candidates) {
            if (closed) throw closedRoute()
            var socket: Socket? = null
            try {
                val slots = RedisEndpoint.open(node, config) { connected ->
                    socket = connected
                    lookups += connected
                    if (closed) closeQuietly(connected) // close() ran meanwhile: it may not have seen it
                }.use { it.sendCommand(Protocol.Command.CLUSTER, "SLOTS") as List<*> }
                val (master, nodes) = parseSlots(slots, node)
                learned = nodes
                known = master
                return master ?: throw JedisConnectionException(
                    "no master of the Redis Cluster $cluster serves hash slot $slot (the slot of this topology): assign " +
                        "every slot to a master (CLUSTER INFO says cluster_state:ok when all are)",
                )
            } catch (e: JedisAccessControlException) {
                throw e // a refused login is the user's to fix, not an outage
            } catch (e: JedisException) {
                if (closed) throw closedRoute().apply { initCause(e) }
                if (e.message?.startsWith("no master of the Redis Cluster") == true) throw e
                failures += "$node: $e"
            } finally {
                socket?.let(lookups::remove)
            }
        }
        // no node answered: an outage, waited out like one (with the master known, on it)
        return last ?: throw JedisConnectionException("no node of the Redis Cluster $cluster answered: ${failures.joinToString("; ")}")
    }

    /** The master of [slot] in a `CLUSTER SLOTS` reply that [asked] gave (`null`: none serves it), and every node it names. */
    private fun parseSlots(reply: List<*>, asked: HostAndPort): Pair<HostAndPort?, List<HostAndPort>> {
        var master: HostAndPort? = null
        val nodes = LinkedHashSet<HostAndPort>()
        for (range in reply) {
            val fields = range as? List<*> ?: continue
            if (fields.size < 3) continue
            val first = (fields[0] as Number).toLong()
            val last = (fields[1] as Number).toLong()
            fields.drop(2).forEachIndexed { i, entry ->
                val node = entry as? List<*> ?: return@forEachIndexed
                val host = when (val h = node[0]) {
                    is ByteArray -> String(h, Charsets.UTF_8)
                    else -> h?.toString().orEmpty()
                }
                // an empty host: the node's address is the one it was asked on
                val address = HostAndPort(host.ifEmpty { asked.host }, (node[1] as Number).toInt())
                nodes += address
                if (i == 0 && slot in first..last) master = address
            }
        }
        return master to nodes.toList()
    }

    override fun close() {
        closed = true
        master = null
        for (socket in lookups.toList()) closeQuietly(socket) // ends a lookup under way; it holds no lock of ours for this
    }

    override fun toString(): String = cluster.toString()

    private fun closedRoute() = JedisConnectionException("the route to the Redis Cluster $cluster is closed")

    private fun closeQuietly(socket: Socket) {
        try {
            socket.close()
        } catch (_: IOException) {
            // closed either way
        }
    }

    private companion object {
        const val RENEW_INTERVAL_MS = 50L
        val DISCOVERY_TIMEOUT: Duration = Duration.ofSeconds(2)
    }
}

package dev.prime.optimus

import redis.clients.jedis.HostAndPort
import redis.clients.jedis.Jedis
import redis.clients.jedis.exceptions.JedisAccessControlException
import redis.clients.jedis.exceptions.JedisClusterOperationException
import redis.clients.jedis.exceptions.JedisConnectionException
import redis.clients.jedis.providers.ClusterConnectionProvider
import java.net.Socket
import java.time.Duration

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
 * Design note. Jedis's cluster client ([ClusterConnectionProvider], what `JedisCluster` is built
 * on) keeps the slot map: it learns it from the seeds at the first [connect] and again after a
 * connection failed or a command was redirected ([routeFailed]: `MOVED`, `ASK`, `CLUSTERDOWN`,
 * `READONLY`, a refused or broken connection), at most once per [RENEW_INTERVAL_MS] and one thread
 * at a time (under [lock]); the others use the map as it is. After a failover the promoted
 * replica is found this way: until the cluster has promoted it, connecting fails (or is
 * redirected) and the callers wait as in an outage.
 */
internal class ClusterRoute(private val cluster: RedisClusterEndpoint, keys: Keys) : RedisTarget {
    /** The hash slot of every key of the topology. */
    val slot: Int = keys.clusterSlot()

    private val lock = Any()
    private var provider: ClusterConnectionProvider? = null // guarded by lock
    private var renewedAt = 0L // guarded by lock
    @Volatile private var master: HostAndPort? = null // null: look it up at the next connect
    @Volatile private var closed = false

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
        synchronized(lock) {
            master?.let { return it }
            if (closed) throw JedisConnectionException("the route to the Redis Cluster $cluster is closed")
            try {
                val known = provider
                if (known == null) {
                    val discovery = minOf(timeout, DISCOVERY_TIMEOUT)
                    val config = RedisEndpoint.clientConfig(
                        cluster.user, cluster.password, cluster.tls, 0, "prime-discovery", discovery, discovery,
                    )
                    provider = ClusterConnectionProvider(cluster.seeds.toSet(), config)
                } else if (System.nanoTime() - renewedAt >= RENEW_INTERVAL_MS * 1_000_000) {
                    known.renewSlotCache()
                }
                renewedAt = System.nanoTime()
            } catch (e: JedisClusterOperationException) {
                // a refused login is the user's to fix, not an outage
                e.suppressed.firstOrNull { it is JedisAccessControlException }?.let { throw it }
                // no node answered: an outage, waited out like one
                val why = e.suppressed.joinToString("; ").ifEmpty { e.message.orEmpty() }
                throw JedisConnectionException("no node of the Redis Cluster $cluster answered: $why", e)
            }
            val node = provider!!.getNode(slot) ?: throw JedisConnectionException(
                "no master of the Redis Cluster $cluster serves hash slot $slot (the slot of this topology): assign " +
                    "every slot to a master (CLUSTER INFO says cluster_state:ok when all are)",
            )
            master = node
            return node
        }
    }

    override fun close() {
        synchronized(lock) {
            closed = true
            master = null
            provider?.close()
            provider = null
        }
    }

    override fun toString(): String = cluster.toString()

    private companion object {
        const val RENEW_INTERVAL_MS = 50L
        val DISCOVERY_TIMEOUT: Duration = Duration.ofSeconds(2)
    }
}

package dev.prime.optimus

import redis.clients.jedis.DefaultJedisClientConfig
import redis.clients.jedis.HostAndPort
import redis.clients.jedis.Jedis
import redis.clients.jedis.Protocol
import redis.clients.jedis.args.ClientType
import redis.clients.jedis.params.ClientKillParams
import redis.clients.jedis.util.JedisClusterCRC16
import java.io.IOException
import java.net.ServerSocket
import java.nio.file.Files
import java.nio.file.Path
import java.time.Duration

/**
 * A real Redis Cluster on loopback for tests: `masters` masters with one replica each, every
 * node a bundled `redis-server` in cluster mode ([EmbeddedRedis]), joined from Java with Jedis
 * the way `redis-cli --cluster create` would (`CLUSTER SET-CONFIG-EPOCH`, `ADDSLOTSRANGE`,
 * `MEET`, `REPLICATE`; no external tool). Client and bus ports are free ones picked at start.
 * Every wait is bounded; [close] stops every node and deletes their directories.
 *
 * The nodes fail over on their own: a master unreachable for `nodeTimeout` is marked failed by
 * the other masters and its replica promotes itself (`cluster-replica-validity-factor 0`: it
 * always may). `cluster-require-full-coverage no` keeps the other masters serving meanwhile.
 *
 * Shared: the cluster tests of this module use it, and so do prime-bench's
 * `ClusterReplicaAcksBenchmark` and prime-faults, through this module's test-jar (which holds
 * this class and [FaultProxy] only): hence public, and [start] callable from Java.
 */
public class LocalRedisCluster private constructor(
    private val root: Path,
    val nodes: List<Node>,
) : AutoCloseable {

    /** One node: its server and the port of its cluster bus. */
    class Node(val redis: EmbeddedRedis, val busPort: Int) {
        val port: Int get() = redis.port
        lateinit var id: String
            internal set

        /** A new connection to this node (2 s timeouts). */
        fun jedis(): Jedis = Jedis(HostAndPort(HOST, port), CONFIG)

        override fun toString(): String = "node $HOST:$port"
    }

    /** The master of the hash slot of [key] now (see [masterOf]); for a topology, any of its keys, e.g. `prime:{name}:`. */
    public fun masterOfKey(key: String): Node = masterOf(JedisClusterCRC16.getSlot(key))

    /** Every node as a seed: `redis-cluster://127.0.0.1:p1,127.0.0.1:p2,...`. */
    val url: String get() = "redis-cluster://" + nodes.joinToString(",") { "$HOST:${it.port}" }

    /** The node that is the master of [slot] now, as a live node sees the cluster. */
    fun masterOf(slot: Int): Node {
        val line = clusterNodes().firstOrNull { line -> "master" in flags(line) && "fail" !in flags(line) && servesSlot(line, slot) }
            ?: throw IllegalStateException("no live master serves slot $slot:\n${clusterNodes().joinToString("\n")}")
        return byId(line.split(' ')[0])
    }

    /** The replica of [master]. */
    fun replicaOf(master: Node): Node {
        val line = clusterNodes().firstOrNull { it.split(' ')[3] == master.id }
            ?: throw IllegalStateException("$master has no replica:\n${clusterNodes().joinToString("\n")}")
        return byId(line.split(' ')[0])
    }

    /**
     * Cuts the replication link of [replica] for good: it may not log in to [master] any more
     * (a bogus `masterauth`: its handshake fails), and `CLIENT KILL TYPE replica` on [master]
     * drops the link. Then lets [master] run ahead for [window] (the length of the fault, not a
     * wait for anything) after it first wrote past what the replica got (at most 5 s); returns by
     * how many bytes the replica is behind.
     */
    fun cutReplicationLink(master: Node, replica: Node, window: Duration): Long {
        replica.jedis().use { it.configSet("masterauth", "no-such-password") }
        master.jedis().use { it.clientKill(ClientKillParams().type(ClientType.REPLICA)) }
        val got = replica.jedis().use { offset(it.info("replication"), "master_repl_offset") }
        await("$master to write past the offset $got of its cut-off replica", Duration.ofSeconds(5)) {
            master.jedis().use { offset(it.info("replication"), "master_repl_offset") } > got
        }
        Thread.sleep(window.toMillis())
        return master.jedis().use { offset(it.info("replication"), "master_repl_offset") } - got
    }

    private fun offset(info: String, field: String): Long =
        info.lines().first { it.startsWith("$field:") }.substringAfter(':').trim().toLong()

    /** Kills [node] with SIGKILL: it saves nothing more, its connections break. */
    fun kill(node: Node) = node.redis.kill()

    /** Starts [node] again on its ports and directory (its `nodes.conf` and data). */
    fun restart(node: Node) = node.redis.restart()

    /** Waits (at most [timeout]) until [node] is the master of [slot] in every live node's view. */
    fun awaitMaster(slot: Int, node: Node, timeout: Duration) {
        await("$node to be the master of slot $slot", timeout) {
            live().all { other ->
                other.jedis().use { jedis ->
                    lines(jedis.clusterNodes()).any { line ->
                        line.startsWith(node.id) && "master" in flags(line) && "fail" !in flags(line) && servesSlot(line, slot)
                    }
                }
            }
        }
    }

    /** Waits (at most [timeout]) until [replica] replicates from [master] with its link up. */
    fun awaitReplica(replica: Node, master: Node, timeout: Duration) {
        await("$replica to replicate $master", timeout) {
            replica.jedis().use { jedis ->
                val info = jedis.info("replication")
                "role:slave" in info && "master_port:${master.port}" in info && "master_link_status:up" in info
            }
        }
    }

    override fun close() {
        for (node in nodes) node.redis.close()
        deleteTree(root)
    }

    private fun live() = nodes.filter { it.redis.isRunning }

    private fun clusterNodes(): List<String> {
        for (node in live()) {
            try {
                return node.jedis().use { lines(it.clusterNodes()) }
            } catch (_: Exception) {
                // a node that just died: ask the next one
            }
        }
        throw IllegalStateException("no node of the cluster answers")
    }

    private fun byId(id: String) = nodes.first { it.id == id }

    companion object {
        private const val HOST = "127.0.0.1"
        private const val SLOTS = 16384
        private val CONFIG = DefaultJedisClientConfig.builder().resp2().autoNegotiateProtocol(false).timeoutMillis(2000).build()
        private val JOIN_TIMEOUT: Duration = Duration.ofSeconds(30)

        /**
         * Starts [masters] masters and as many replicas, joined into one cluster with every slot
         * assigned; waits until every node says `cluster_state:ok` and every replica is in sync.
         * [appendOnly]: every node keeps an append-only file synced on every write.
         */
        @JvmStatic
        @JvmOverloads
        fun start(masters: Int = 3, nodeTimeout: Duration = Duration.ofMillis(1000), appendOnly: Boolean = false): LocalRedisCluster {
            val root = Files.createTempDirectory("prime-cluster-")
            val nodes = ArrayList<Node>()
            try {
                val ports = HashSet<Int>()
                repeat(2 * masters) { index ->
                    val port = freePort(ports)
                    val bus = freePort(ports)
                    val dir = root.resolve("node-$index")
                    Files.createDirectories(dir)
                    val builder = EmbeddedRedis.builder().port(port)
                    // the node's nodes.conf lives in its directory, so a restarted node knows its cluster
                    if (appendOnly) builder.appendOnlyDir(dir)
                    val redis = builder.arguments(
                        "--dir", dir.toString(),
                        "--cluster-enabled", "yes",
                        "--cluster-config-file", "nodes.conf",
                        "--cluster-node-timeout", nodeTimeout.toMillis().toString(),
                        "--cluster-port", bus.toString(),
                        "--cluster-require-full-coverage", "no",
                        "--cluster-replica-validity-factor", "0",
                        "--cluster-allow-replica-migration", "no",
                    ).start()
                    nodes += Node(redis, bus)
                }
                val cluster = LocalRedisCluster(root, nodes)
                cluster.join(masters)
                return cluster
            } catch (e: Throwable) {
                for (node in nodes) node.redis.close()
                deleteTree(root)
                throw e
            }
        }

        private fun LocalRedisCluster.join(masters: Int) {
            nodes.forEachIndexed { index, node ->
                node.jedis().use { jedis ->
                    node.id = jedis.clusterMyId()
                    // distinct epochs from the start: no collision to resolve after the meet
                    jedis.sendCommand(Protocol.Command.CLUSTER, "SET-CONFIG-EPOCH", (index + 1).toString())
                }
            }
            for (m in 0 until masters) {
                val first = m * SLOTS / masters
                val last = (m + 1) * SLOTS / masters - 1
                nodes[m].jedis().use { it.sendCommand(Protocol.Command.CLUSTER, "ADDSLOTSRANGE", first.toString(), last.toString()) }
            }
            nodes[0].jedis().use { jedis ->
                for (node in nodes.drop(1)) {
                    jedis.sendCommand(Protocol.Command.CLUSTER, "MEET", HOST, node.port.toString(), node.busPort.toString())
                }
            }
            await("every node to know all ${nodes.size}", JOIN_TIMEOUT) {
                nodes.all { node ->
                    val lines = node.jedis().use { lines(it.clusterNodes()) }
                    lines.size == nodes.size && lines.none { "handshake" in flags(it) || "noaddr" in flags(it) }
                }
            }
            for (r in 0 until masters) {
                nodes[masters + r].jedis().use { it.clusterReplicate(nodes[r].id) }
            }
            for (r in 0 until masters) awaitReplica(nodes[masters + r], nodes[r], JOIN_TIMEOUT)
            await("every node to see the replicas and cluster_state:ok", JOIN_TIMEOUT) {
                nodes.all { node ->
                    node.jedis().use { jedis ->
                        "cluster_state:ok" in jedis.clusterInfo() &&
                            lines(jedis.clusterNodes()).count { "slave" in flags(it) } == masters
                    }
                }
            }
        }

        private fun lines(text: String) = text.lines().map { it.trim() }.filter { it.isNotEmpty() }

        private fun flags(line: String): List<String> = line.split(' ')[2].split(',')

        /** Whether a `CLUSTER NODES` line lists [slot] among its slot ranges. */
        private fun servesSlot(line: String, slot: Int): Boolean = line.split(' ').drop(8).any { range ->
            if (range.startsWith("[")) return@any false // a slot being migrated
            val parts = range.split('-')
            val first = parts[0].toInt()
            val last = if (parts.size > 1) parts[1].toInt() else first
            slot in first..last
        }

        /** Polls [done] every 20 ms until it holds, at most [timeout]; failures of [done] count as "not yet". */
        fun await(what: String, timeout: Duration, done: () -> Boolean) {
            val deadline = System.nanoTime() + timeout.toNanos()
            var last: Exception? = null
            while (System.nanoTime() < deadline) {
                try {
                    if (done()) return
                } catch (e: Exception) {
                    last = e
                }
                Thread.sleep(20)
            }
            throw AssertionError("waited $timeout for $what" + (last?.let { "; last error: $it" } ?: ""))
        }

        private fun freePort(taken: MutableSet<Int>): Int {
            repeat(100) {
                // a bus port is the client port's + 10000 by default; this one is set explicitly, any free one does
                val port = ServerSocket(0).use { it.localPort }
                if (taken.add(port)) return port
            }
            throw IllegalStateException("no free port found")
        }

        private fun deleteTree(dir: Path) {
            try {
                Files.walk(dir).use { paths -> paths.sorted(Comparator.reverseOrder()).forEach { Files.deleteIfExists(it) } }
            } catch (_: IOException) {
                // a temporary directory left behind is harmless
            }
        }
    }
}

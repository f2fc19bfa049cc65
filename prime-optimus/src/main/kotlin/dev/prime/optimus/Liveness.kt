package dev.prime.optimus

import dev.prime.CoreClosedException
import org.slf4j.LoggerFactory
import redis.clients.jedis.Jedis
import redis.clients.jedis.Pipeline
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration
import java.util.UUID
import java.util.concurrent.atomic.AtomicLong

/** Why an instance must declare again what it hosts and reads. */
internal enum class Loss {
    /** Redis lost the topology's data: restarted without persistence, or failed over to a replica that was behind. */
    DATA_LOST,

    /** Redis came back behind: it lacks this instance's last declarations (a replica that lagged, an everysec AOF). */
    WRITES_LOST,

    /** This instance's lease lapsed (frozen or cut off longer than the lease): others may have reclaimed its lists. */
    LEASE_LAPSED,
}

/** What the heartbeat does besides renewing the instance lease; both run on the heartbeat thread. */
internal interface LivenessHooks {
    /** Declares again everything the instance hosts and reads; throws if Redis fails (tried again on the next beat). */
    fun redeclare(session: RedisSession, loss: Loss)

    /** Renews what else has a lease (the host leases of services). */
    fun renew(session: RedisSession)
}

/**
 * The liveness lease of one core instance, its heartbeat, and the reclaiming of dead instances.
 *
 * Design note. The instance registers its id in the topology's instance set and holds a lease key
 * (`SET PX`, [leaseTime]) that a heartbeat renews every third of the lease time; every reader list
 * and reply list it creates is recorded in its own hash ([own]) before it is used. Each beat:
 * 1. renews the lease in [LeaseScripts.HEARTBEAT], which also reads the topology's epoch (a random
 *    token written once per life of the data). A new epoch means Redis lost the data; a lease that
 *    was gone means this instance was taken for dead. Either way [LivenessHooks.redeclare] runs,
 *    and again on later beats until it succeeded;
 * 2. calls [LivenessHooks.renew] (host leases);
 * 3. reclaims every instance of the set whose lease is gone: its reader lists leave their sources'
 *    reader sets and are deleted, with its reply lists ([LeaseScripts.RECLAIM], which does nothing
 *    if the lease came back meanwhile). An instance reclaims only after it has held its own lease
 *    for a lease time without a failed beat, so that after an outage of Redis the others have had
 *    a beat to renew theirs.
 *
 * The heartbeat is one task on the core's executor; it waits with [RedisConnections.pause], so
 * closing the connections ends it at once. Beats start a third of the lease time apart, counted
 * from the start of the last one (at once after a beat that took longer): a beat costs about five
 * round trips to Redis, which over a slow link would otherwise stretch the time between two
 * renewals past the lease. The first beat runs on the caller of [begin], so the
 * lease exists before anything is registered.
 */
internal class Liveness(
    private val keys: Keys,
    private val connections: RedisConnections,
    /** The instance id (random per core). */
    val instance: String,
    val leaseTime: Duration,
    private val launcher: (Runnable) -> Unit,
    private val hooks: LivenessHooks,
) {
    private val lease = keys.instanceLease(instance)
    private val lists = keys.instanceLists(instance)
    private val declared = keys.instanceDeclared(instance)
    private val declarations = AtomicLong() // how many this instance made: Redis must hold at least that
    private val instanceId = instance.toByteArray(UTF_8)
    private val leaseValue = describeProcess().toByteArray(UTF_8)
    private val leaseMillis = leaseTime.toMillis().toString().toByteArray(UTF_8)
    private val interval = (leaseTime.toMillis() / 3).coerceAtLeast(1)
    private val beginLock = Any()
    private val resetCount = AtomicLong()
    private val lapseCount = AtomicLong()

    @Volatile
    private var begun = false

    // written by the first beat (under beginLock, before the heartbeat starts) and then by the heartbeat only
    private var knownEpoch: String? = null
    private var pending: Loss? = null
    private var reclaimNotBefore = 0L

    /** How many times Redis was found to have lost the topology's data. */
    val resets: Long get() = resetCount.get()

    /** How many times this instance found its own lease gone. */
    val lapses: Long get() = lapseCount.get()

    /**
     * Registers the instance and starts the heartbeat, once; waits while Redis is unreachable.
     *
     * @throws CoreClosedException once the core is closed
     */
    fun begin() {
        if (begun) return
        synchronized(beginLock) {
            if (begun) return
            RedisSession(connections).use { session -> session.retrying(::beatOnce) }
            reclaimNotBefore = System.nanoTime() + leaseTime.toNanos()
            launcher(Runnable { heartbeat() })
            begun = true
        }
    }

    /**
     * Records that this instance owns [list], a reader list in [readerSet] or (if `null`) a reply
     * list; while Redis is unreachable it retries until [deadline] (`null`: for as long as it
     * takes), then throws [RedisUnavailableException] naming [what].
     */
    fun own(session: RedisSession, list: ByteArray, readerSet: ByteArray?, deadline: Long? = null, what: String = "") {
        begin()
        session.retryingUntil(deadline, what) { jedis ->
            val pipeline = jedis.pipelined()
            pipeline.hset(lists, list, readerSet ?: EMPTY)
            val count = pipeline.incr(declared)
            pipeline.sync()
            declarations.accumulateAndGet(count.get(), ::maxOf)
        }
    }

    /**
     * Counts a declaration this instance just made (a registration with a source), so the
     * heartbeat notices if Redis loses it (a crash with `appendfsync everysec`, a replica that was
     * behind): Redis writes in order, so a lost declaration takes the later count with it.
     */
    fun declared(session: RedisSession) {
        begin()
        session.retrying { declarations.accumulateAndGet(it.incr(declared), ::maxOf) }
    }

    /** Queues forgetting [list] (a reader that unregistered itself). */
    fun disown(pipeline: Pipeline, list: ByteArray) {
        if (begun) pipeline.hdel(lists, list)
    }

    /** Queues the removal of the lease and the ownership records (the lists themselves are the caller's). */
    fun releaseAll(pipeline: Pipeline) {
        if (!begun) return
        pipeline.del(lease, lists, declared)
        pipeline.srem(keys.instances, instanceId)
    }

    private fun heartbeat() {
        RedisSession(connections).use { session ->
            val outage = OutageCauses()
            var beganAt = System.nanoTime()
            while (!connections.isClosed) {
                try {
                    // from the start of the last beat: its round trips must not stretch the time between renewals
                    connections.pause((interval - (System.nanoTime() - beganAt) / 1_000_000).coerceAtLeast(1))
                    if (connections.isClosed) return
                    beganAt = System.nanoTime()
                    beat(session)
                    if (outage.end()) LOG.info("the heartbeat of instance {} reaches Redis again", instance)
                } catch (_: CoreClosedException) {
                    return
                } catch (e: Exception) {
                    if (connections.isClosed) return
                    if (outage.isNew(e)) {
                        LOG.warn(
                            "the heartbeat of instance {} of topology '{}' failed ({}); its lease lapses after {} ms unless a " +
                                "beat succeeds",
                            instance, connections.coreName, e.toString(), leaseTime.toMillis(),
                        )
                    }
                    reclaimNotBefore = System.nanoTime() + leaseTime.toNanos()
                }
            }
        }
    }

    private fun beat(session: RedisSession) {
        session.once(::beatOnce)
        pending?.let { loss ->
            reclaimNotBefore = System.nanoTime() + leaseTime.toNanos()
            val count = declarations.get()
            hooks.redeclare(session, loss)
            // what was declared again is counted anew; declarations made meanwhile raise it further
            session.once { LeaseScripts.RAISE.run(it, listOf(declared), listOf(count.toString().toByteArray(UTF_8))) }
            pending = null
        }
        hooks.renew(session)
        if (System.nanoTime() - reclaimNotBefore >= 0) reclaimDead(session)
    }

    /** Renews the lease; notes a loss of data or of the lease. */
    private fun beatOnce(jedis: Jedis) {
        val fresh = UUID.randomUUID().toString().toByteArray(UTF_8)
        val expected = declarations.get()
        val reply = LeaseScripts.HEARTBEAT.run(
            jedis,
            listOf(lease, keys.instances, keys.epoch, declared),
            listOf(instanceId, leaseValue, leaseMillis, fresh),
        ) as List<*>
        val epoch = (reply[0] as ByteArray).toString(UTF_8)
        val leaseWasAlive = reply[1] == 1L
        val stored = reply[2] as Long
        val known = knownEpoch
        knownEpoch = epoch
        if (known == null) return
        // no count at all with a lapsed lease: reclaimed as dead; a smaller count: Redis lost writes
        val writesLost = expected > 0 && if (stored < 0) leaseWasAlive else stored < expected
        if (epoch != known || writesLost) {
            if (pending != Loss.DATA_LOST && pending != Loss.WRITES_LOST) resetCount.incrementAndGet()
            pending = if (epoch != known) Loss.DATA_LOST else Loss.WRITES_LOST
        } else if (!leaseWasAlive) {
            lapseCount.incrementAndGet()
            if (pending == null) pending = Loss.LEASE_LAPSED
        }
    }

    private fun reclaimDead(session: RedisSession) {
        val others = session.once { it.smembers(keys.instances) }.map { it.toString(UTF_8) }.filter { it != instance }
        if (others.isEmpty()) return
        val alive = session.once { jedis ->
            val pipeline = jedis.pipelined()
            val answers = others.map { pipeline.exists(keys.instanceLease(it)) }
            pipeline.sync()
            answers.map { it.get() }
        }
        others.forEachIndexed { i, other -> if (!alive[i]) reclaim(session, other) }
    }

    private fun reclaim(session: RedisSession, dead: String) {
        val owned = session.once { it.hgetAll(keys.instanceLists(dead)) }.entries.toList()
        var readers = 0
        var replies = 0
        var start = 0
        do {
            val chunk = owned.subList(start, minOf(start + RECLAIM_CHUNK, owned.size))
            val scriptKeys =
                arrayListOf(keys.instanceLease(dead), keys.instances, keys.instanceLists(dead), keys.instanceDeclared(dead))
            val args = arrayListOf(dead.toByteArray(UTF_8), MISSED_KEPT_MS)
            for ((list, readerSet) in chunk) {
                if (readerSet.isNotEmpty()) {
                    scriptKeys += listOf(list, keys.processingOf(list), keys.missedOf(list), readerSet)
                    args += READER_KEYS
                    readers++
                } else {
                    scriptKeys += list
                    args += REPLY_KEYS
                    replies++
                }
            }
            if (session.once { LeaseScripts.RECLAIM.run(it, scriptKeys, args) } == -1L) return // it renewed its lease
            start += chunk.size
        } while (start < owned.size)
        if (readers + replies > 0) {
            LOG.warn(
                "instance {} of topology '{}' let its lease expire (its process died or was cut off longer than {} ms): " +
                    "reclaimed its {} reader list(s) and {} reply list(s); values unread in them are gone",
                dead, connections.coreName, leaseTime.toMillis(), readers, replies,
            )
        }
    }

    internal companion object {
        private val LOG = LoggerFactory.getLogger(Liveness::class.java)
        private val EMPTY = ByteArray(0)
        private val READER_KEYS = "4".toByteArray(UTF_8)
        private val REPLY_KEYS = "1".toByteArray(UTF_8)

        /**
         * How long a reclaimed reader's missed counter is kept (an hour): a process cut off no
         * longer than that declares the reader again and keeps counting from there.
         */
        const val MISSED_KEPT_MILLIS = 3_600_000L
        private val MISSED_KEPT_MS = MISSED_KEPT_MILLIS.toString().toByteArray(UTF_8)

        /** Lists reclaimed per script call, so one call never blocks Redis long. */
        private const val RECLAIM_CHUNK = 256

        /** "pid 1234 on host", for messages that name the holder of a lease. */
        private fun describeProcess(): String {
            val host = System.getenv("HOSTNAME") ?: System.getenv("COMPUTERNAME") ?: "an unnamed host"
            return "pid ${ProcessHandle.current().pid()} on $host"
        }
    }
}

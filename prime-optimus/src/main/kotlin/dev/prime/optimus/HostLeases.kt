package dev.prime.optimus

import redis.clients.jedis.Jedis
import redis.clients.jedis.Pipeline
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration
import java.util.concurrent.ConcurrentHashMap
import java.util.concurrent.locks.ReentrantLock

/**
 * The host leases of the services one core instance runs: a service has one host at a time.
 *
 * Design note. A host lease is a key holding the id of the instance that runs the service, set
 * with `SET NX PX` semantics (in [LeaseScripts.HOST_CLAIM], which also renews a lease the instance
 * holds) and renewed by the heartbeat every third of the lease time ([LeaseScripts.HOST_RENEW],
 * which re-claims a lapsed lease only for a service without a processing list: one with a list
 * does, as it reads the list again). [claim] waits at most one
 * lease time (plus [CLAIM_MARGIN]) for a lease held by another instance to lapse, so a restarted
 * worker takes over from a killed one; a live holder renews its lease and the claim fails
 * ([Hosting.EXCLUSIVE]). A standby of an [Hosting.ORDERED] service calls [tryClaim] instead, which
 * never waits, until the lease is free. The
 * set of held services is a concurrent set: [claim] runs on declaring threads, [renew] on the
 * heartbeat thread, [drop] on a service whose step the script fenced (see [Script.STEP]); a lease
 * found taken is removed from it once, by whichever of them sees it first. [releaseAll] releases
 * the leases of every service this instance ever tried to claim, not only the held ones: a
 * standby's claim that Redis granted while the core closed may not be in the held set yet, and
 * releasing a lease another instance holds changes nothing ([LeaseScripts.HOST_RELEASE] checks
 * the holder), so the next standby takes over within a third of the lease instead of a whole one.
 * A renewal and a [release] are serialised by [renewal]: a renewal holds it from its snapshot of
 * the held set until its script has run, and a release removes its services from the held set
 * under it, so a renewal sent before a release ends before the release deletes, and one after it
 * no longer names the released services: a released lease is never written again by a renewal
 * (which re-claims a lapsed one for a service without a processing list). The release waits at
 * most one renewal's round trip; neither adds one.
 */
internal class HostLeases(
    private val keys: Keys,
    private val connections: RedisConnections,
    private val instance: String,
    private val leaseTime: Duration,
    /** Whether a service re-claims its lapsed lease itself, as it reads its processing list ([Script.PEEK]). */
    private val reclaimsItsOwnLease: (String) -> Boolean,
) {
    private val held: MutableSet<String> = ConcurrentHashMap.newKeySet()

    /** Every service a claim of this instance named: what [releaseAll] releases. */
    private val claimed: MutableSet<String> = ConcurrentHashMap.newKeySet()
    private val instanceId = instance.toByteArray(UTF_8)
    private val leaseMillis = leaseTime.toMillis().toString().toByteArray(UTF_8)

    /** Held by [renew] from its snapshot of [held] to its script's reply; [release] updates [held] under it. */
    private val renewal = ReentrantLock()

    /** Test seam: runs in [renew] between its snapshot of the held leases and its script. */
    @Volatile
    internal var beforeRenewScript: () -> Unit = {}

    /** Test seam: runs in [release] when it finds a renewal in flight, before it waits for it. */
    @Volatile
    internal var releaseWaitsForRenewal: () -> Unit = {}

    /** The services whose lease this instance holds. */
    val services: Set<String> get() = held.toSet()

    /**
     * Claims the leases of [services], waiting up to one lease time for leases of other instances
     * to lapse, for `start()`, or for [declaration] (what was declared after `start()`, such as
     * "chain 'a>b' declared after start()"; [ofAChain]: it is a chain's, which stays unused when
     * refused, so its refusal says that the same chain can be declared again).
     *
     * @throws IllegalStateException naming each service another live instance still hosts (the
     *     leases claimed by this call are released again)
     */
    fun claim(services: Collection<String>, coreName: String, declaration: String? = null, ofAChain: Boolean = false) {
        if (services.isEmpty()) return
        val started = System.nanoTime()
        val deadline = started + leaseTime.toNanos() + CLAIM_MARGIN.toNanos()
        val all = services.toList()
        val heldBefore = held.toSet()
        claimed += all
        try {
            claimWaiting(all, coreName, declaration, ofAChain, started, deadline)
        } catch (e: Exception) {
            if (e is IllegalStateException) throw e // refused: the refusal released what it was granted
            // the claim may have reached Redis and been granted, its answer lost (an interrupt, a
            // broken connection), or it was granted some and waited for others: give back what it
            // may hold, or no other process could host those services for a lease time
            releaseAfterFailedClaim(all.filter { it !in heldBefore && it !in held })
            throw e
        }
    }

    private fun claimWaiting(all: List<String>, coreName: String, declaration: String?, ofAChain: Boolean, started: Long, deadline: Long) {
        RedisSession(connections).use { session ->
            while (true) {
                // all of them each time: this renews the leases already claimed while others are awaited
                val holders = session.retrying { claimOnce(it, all) }
                val claimed = ArrayList<String>()
                val refused = LinkedHashMap<String, String>()
                var soonest = Long.MAX_VALUE
                all.forEachIndexed { i, service ->
                    val (holder, remaining) = holders[i]
                    if (holder == instance) {
                        claimed += service
                    } else {
                        refused[service] = holder
                        soonest = minOf(soonest, remaining)
                    }
                }
                if (refused.isEmpty()) {
                    held += claimed
                    return
                }
                val left = deadline - System.nanoTime()
                if (left <= 0) {
                    val described = refused.entries.joinToString("; ") { (service, holder) ->
                        "service '$service' is already hosted by ${describe(session, holder)}"
                    }
                    if (claimed.isNotEmpty()) session.retrying { release(it, claimed) }
                    val waited = Duration.ofNanos(System.nanoTime() - started).toMillis()
                    val advice = "A service has one host at a time: remove it from hosts(...) of one of the " +
                        "processes, or stop the other one (the lease of a killed host lapses within the lease time, " +
                        "${leaseTime.toMillis()} ms)"
                    throw IllegalStateException(
                        if (declaration == null) {
                            "core '$coreName' cannot start: $described, which kept its host lease during the $waited ms " +
                                "start() waited. $advice"
                        } else {
                            "core '$coreName' cannot host $declaration: $described, which kept its host lease during " +
                                "the $waited ms the declaration waited. $advice. The declaration left nothing behind: it " +
                                "can be made again${if (ofAChain) ", on the same chain," else ""} once the other host is gone"
                        },
                    )
                }
                val wait = (soonest + 1).coerceIn(MIN_WAIT_MS, ceilMillis(left))
                connections.pause(wait)
            }
        }
    }

    /**
     * Releases the leases of [services] after a claim of them failed when it may have been granted
     * (its answer lost, or it waited for others'): once, within [RELEASE_AFTER_FAILED_CLAIM], and
     * whatever the thread's interrupt flag (an interrupt may be what ended the claim), else each
     * lapses within the lease time. The release script checks the holder: a lease this instance
     * does not hold is left as it is. Not on a closed core: its close releases every lease it
     * claimed ([releaseAll]).
     */
    private fun releaseAfterFailedClaim(services: List<String>) {
        if (services.isEmpty() || connections.isClosed) return
        val aborts = RedisSession.ABORTS_ON_INTERRUPT.get()
        RedisSession.ABORTS_ON_INTERRUPT.set(null)
        try {
            RedisSession(connections).use { session ->
                session.once(System.nanoTime() + RELEASE_AFTER_FAILED_CLAIM.toNanos(), 0) { release(it, services) }
            }
        } catch (e: Exception) {
            LOG.debug("could not release the host leases of {} after a failed claim (they lapse within {}): {}", services, leaseTime, e.toString())
        } finally {
            RedisSession.ABORTS_ON_INTERRUPT.set(aborts)
        }
    }

    /**
     * Claims the leases of [services] once, without waiting (a standby of an [Hosting.ORDERED]
     * service); returns those another instance holds, each with the milliseconds its lease has left.
     */
    fun tryClaim(jedis: Jedis, services: List<String>): Map<String, Long> {
        if (services.isEmpty()) return emptyMap()
        claimed += services // before Redis can grant any: a close from now on releases them
        val holders = claimOnce(jedis, services)
        val refused = LinkedHashMap<String, Long>()
        services.forEachIndexed { i, service ->
            val (holder, remaining) = holders[i]
            if (holder == instance) held += service else refused[service] = remaining
        }
        return refused
    }

    /**
     * Renews every held lease; returns the services whose lease another instance holds now, with
     * that holder. Those are no longer held. A lease that is gone (it lapsed while this instance
     * was frozen or cut off, or Redis lost its data) is claimed again here only for a service that
     * holds no batch (a generic service); a service with a processing list re-claims it itself,
     * when it reads the list again ([Script.PEEK]): the batch it held may be stale (another host
     * may have held the lease meanwhile), so only a fresh read may follow a fresh claim.
     */
    fun renew(jedis: Jedis): Map<String, String> {
        val services: List<String>
        val reply: List<*>
        renewal.lock()
        try {
            services = held.toList()
            if (services.isEmpty()) return emptyMap()
            val reclaim = services.joinToString("") { if (reclaimsItsOwnLease(it)) "0" else "1" }.toByteArray(UTF_8)
            beforeRenewScript()
            reply = LeaseScripts.HOST_RENEW.run(jedis, services.map(keys::hostLease), listOf(instanceId, leaseMillis, reclaim)) as List<*>
        } finally {
            renewal.unlock()
        }
        val taken = LinkedHashMap<String, String>()
        services.forEachIndexed { i, service ->
            val holder = (reply[2 * i] as ByteArray).toString(UTF_8)
            if (holder.isNotEmpty() && holder != instance && held.remove(service)) taken[service] = holder
        }
        return taken
    }

    /**
     * Gives up the leases of [services], which a declaration that failed claimed: no longer
     * renewed, and released in Redis once, if Redis answers (else each lapses within the lease
     * time), so that another process can host them. A renewal in flight ends first (see the
     * design note): no renewal writes a released lease again.
     */
    fun release(services: Collection<String>) {
        if (services.isEmpty()) return
        if (!renewal.tryLock()) {
            releaseWaitsForRenewal()
            renewal.lock()
        }
        try {
            held -= services.toSet()
        } finally {
            renewal.unlock()
        }
        try {
            RedisSession(connections).use { session -> session.once { release(it, services.toList()) } }
        } catch (e: Exception) {
            LOG.debug("could not release the host leases of {} at once (they lapse within {}): {}", services, leaseTime, e.toString())
        }
    }

    /**
     * Forgets [service]'s lease, which a step of it found held by another instance; `false` if it
     * was not held any more (the heartbeat saw it first).
     */
    fun drop(service: String): Boolean = held.remove(service)

    /**
     * Queues the release of the lease of every service this instance claimed or tried to claim,
     * held or not (Redis deletes only those this instance still holds).
     */
    fun releaseAll(pipeline: Pipeline) {
        val services = (claimed + held).toList()
        held.clear()
        if (services.isNotEmpty()) LeaseScripts.HOST_RELEASE.queue(pipeline, services.map(keys::hostLease), listOf(instanceId))
    }

    /** Who [holder] is: its id and, while its instance lease lives, the process it names. */
    fun describe(session: RedisSession, holder: String): String {
        val process = try {
            session.once { it.get(keys.instanceLease(holder)) }?.toString(UTF_8)
        } catch (_: Exception) {
            null
        }
        return "instance $holder" + (process?.let { " ($it)" } ?: "")
    }

    private fun claimOnce(jedis: Jedis, services: List<String>): List<Pair<String, Long>> {
        val reply = LeaseScripts.HOST_CLAIM.run(jedis, services.map(keys::hostLease), listOf(instanceId, leaseMillis)) as List<*>
        return services.indices.map { i -> (reply[2 * i] as ByteArray).toString(UTF_8) to (reply[2 * i + 1] as Long) }
    }

    private fun release(jedis: Jedis, services: List<String>) {
        LeaseScripts.HOST_RELEASE.run(jedis, services.map(keys::hostLease), listOf(instanceId))
    }

    private companion object {
        val LOG: org.slf4j.Logger = org.slf4j.LoggerFactory.getLogger(HostLeases::class.java)

        /** Slack over the lease time when waiting for another's lease to lapse (timer and network jitter). */
        val CLAIM_MARGIN: Duration = Duration.ofMillis(200)
        const val MIN_WAIT_MS = 10L

        /** The most a failed claim waits for the release of what it may have been granted (see [releaseAfterFailedClaim]). */
        val RELEASE_AFTER_FAILED_CLAIM: Duration = Duration.ofMillis(500)

        fun ceilMillis(nanos: Long): Long = ((nanos + 999_999) / 1_000_000).coerceAtLeast(1)
    }
}

package dev.prime.optimus

import org.slf4j.LoggerFactory
import redis.clients.jedis.Jedis
import redis.clients.jedis.Pipeline
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration
import java.util.UUID
import java.util.concurrent.ConcurrentHashMap

/** Where one run of a hosted service keeps what it took, and the lease its steps are fenced by. */
internal class HostSeat(
    val service: String,
    /** The processing list of this run: the service's own (one host at a time) or this host's (unordered). */
    val processing: ByteArray,
    val fence: HostFence,
    /** Whether other hosts take from the same input at the same time ([Hosting.UNORDERED]). */
    val shared: Boolean,
    /** How long a blocking take may wait in Redis, in seconds. */
    val idleWaitSeconds: Double,
    /**
     * For a shared seat, the service's host set and this host's id in it: a blocking take is
     * followed in Redis by [HostingScripts.CHECK_SEATED] on them; `null` for a service's own seat.
     */
    val membership: Pair<ByteArray, ByteArray>? = null,
) {
    private var nanosPerEntry = 0.0

    /**
     * How many entries the next step takes, after [entries] took [nanos] to handle: all that fit
     * (up to [StageService.BATCH]) for a service with one host; for a shared one about
     * [SHARED_STEP_NANOS] of work as measured, so the hosts share the queue at that grain instead
     * of the first one taking a whole batch of a slow block's values.
     */
    fun nextTake(entries: Int, nanos: Long): Int {
        if (!shared) return StageService.BATCH
        if (entries > 0) {
            val sample = nanos.toDouble() / entries
            nanosPerEntry = if (nanosPerEntry == 0.0) sample else 0.7 * nanosPerEntry + 0.3 * sample
        }
        if (nanosPerEntry <= 0.0) return 1
        return (SHARED_STEP_NANOS / nanosPerEntry).toInt().coerceIn(1, StageService.BATCH)
    }

    private companion object {
        /** The work one step of a shared service takes on: 5 ms (a round trip per step costs ~0.1 ms). */
        const val SHARED_STEP_NANOS = 5_000_000.0
    }
}

/**
 * The hosting modes ([Hosting]) of the services one core instance hosts, and the seats of its
 * [Hosting.UNORDERED] services.
 *
 * Design note. A service's mode is recorded in Redis (`svc:<s>:hosting`) by its hosts, with the
 * lease time as expiry, renewed by each host's heartbeat: a process that declares another mode is
 * refused at `start()`; the record lapses a lease time after the last host stopped, so a changed
 * mode can be deployed by stopping the old hosts. An unordered host's seat (see [HostingScripts])
 * carries a token that is new for every run of the service: the heartbeat only renews a lease
 * that still holds the token ([HostingScripts.RENEW]). A lease that lapsed (the process was
 * frozen or cut off longer than the lease, or Redis lost it) may have been reclaimed by another
 * host, which moved the entries of this host's processing list back to the input; so the run that
 * held it must store nothing more: the core starts a new run with a new token, and the old run's
 * steps are fenced by that token. Each heartbeat also reclaims the seats of dead hosts of the
 * services this instance hosts unordered ([reclaimDead]); so does taking a seat (a host restarted
 * after all hosts died takes its predecessors' entries at once). Maps are concurrent: declaring and
 * starting threads write them, the heartbeat reads them.
 */
internal class SharedHosting(
    private val keys: Keys,
    private val instance: String,
    private val leaseTime: Duration,
    /** The mode of each service whose mode was set ([OptimusCore.Builder.hosting]). */
    private val declared: Map<String, Hosting>,
) {
    private val leaseMillis = leaseTime.toMillis().toString().toByteArray(UTF_8)
    private val instanceId = instance.toByteArray(UTF_8)
    private val idleWaitSeconds = minOf(RedisConnections.POLL_SECONDS, leaseTime.toMillis() / 3 / 1000.0)

    /** The services whose mode this instance renews: those it hosts (running or standing by). */
    private val renewed: MutableMap<String, Hosting> = ConcurrentHashMap()

    /** The current seat of each unordered service this instance runs, and whether its queue count is kept. */
    private val seats: MutableMap<String, Pair<HostSeat, Boolean>> = ConcurrentHashMap()

    fun modeOf(service: String): Hosting = declared[service] ?: Hosting.EXCLUSIVE

    /** The services given a mode other than the default. */
    val nonDefault: Set<String> get() = declared.filterValues { it != Hosting.EXCLUSIVE }.keys

    /**
     * Records the modes of [services] (which this instance hosts) in Redis, or checks them against
     * the modes other hosts recorded.
     *
     * @throws IllegalStateException naming each service whose hosts declared another mode, and the fix
     */
    fun declare(session: RedisSession, services: Collection<String>, coreName: String) {
        if (services.isEmpty()) return
        val all = services.toList()
        val recorded = session.retrying { modes(it, all) }
        val disagreeing = all.indices.filter { recorded[it] != modeOf(all[it]).name }
        if (disagreeing.isNotEmpty()) {
            val described = disagreeing.joinToString("; ") { i ->
                "service '${all[i]}' is hosted ${recorded[i]} by other processes, this one declares ${modeOf(all[i])}"
            }
            throw IllegalStateException(
                "core '$coreName' cannot start: $described. Every process that hosts a service must declare the same " +
                    "hosting mode: set OptimusCore.Builder.hosting(service, Hosting.X) alike in all of them (EXCLUSIVE is " +
                    "the default). To change a service's mode on purpose, stop the processes that host it with the old " +
                    "mode: their record (Redis key ${keys.hostingMode(all[disagreeing.first()]).toString(UTF_8)}) lapses " +
                    "${leaseTime.toMillis()} ms after the last of them stopped",
            )
        }
        all.forEach { renewed[it] = modeOf(it) }
    }

    /** Whether this instance recorded [service]'s mode already. */
    fun isDeclared(service: String): Boolean = service in renewed

    /** Takes a new seat for a run of unordered [service] (a new token), after reclaiming the seats of dead hosts. */
    fun claim(session: RedisSession, service: String, counted: Boolean): HostSeat {
        val token = "$instance/${UUID.randomUUID()}"
        val seat = HostSeat(
            service,
            keys.hostProcessing(service, instance),
            HostFence(keys.hostSeatLease(service, instance), token.toByteArray(UTF_8)),
            shared = true,
            idleWaitSeconds = idleWaitSeconds,
            membership = keys.serviceHosts(service) to instanceId,
        )
        session.retrying { jedis ->
            HostingScripts.CLAIM.run(jedis, listOf(seat.fence.lease, keys.serviceHosts(service)), listOf(seat.fence.instance, leaseMillis, instanceId))
        }
        seats[service] = seat to counted
        session.retrying { reclaimDead(it, service, counted) }
        return seat
    }

    /** Whether [seat] is still the current seat of its service here (a superseded run stops quietly). */
    fun isCurrent(seat: HostSeat): Boolean = seats[seat.service]?.first === seat

    /**
     * Renews the modes and the seats, and reclaims the seats of dead hosts; returns the unordered
     * services whose seat lapsed (their runs must start anew), which are no longer seated.
     */
    fun renew(jedis: Jedis): List<String> {
        val modes = renewed.entries.toList()
        if (modes.isNotEmpty()) {
            val recorded = modes(jedis, modes.map { it.key })
            modes.forEachIndexed { i, (service, mode) ->
                if (recorded[i] != mode.name) {
                    LOG.error(
                        "service '{}' is recorded as hosted {} in Redis, this process hosts it {}: the processes of its " +
                            "topology disagree on its hosting (every host of a service must declare the same mode)",
                        service, recorded[i], mode,
                    )
                }
            }
        }
        val current = seats.values.toList()
        if (current.isEmpty()) return emptyList()
        val renewedSeats = HostingScripts.RENEW.run(
            jedis,
            current.map { it.first.fence.lease },
            listOf(leaseMillis) + current.map { it.first.fence.instance },
        ) as List<*>
        val lapsed = ArrayList<String>()
        current.forEachIndexed { i, (seat, counted) ->
            if (renewedSeats[i] == 1L) {
                reclaimDead(jedis, seat.service, counted)
            } else if (seats.remove(seat.service, seat to counted)) {
                lapsed += seat.service
            }
        }
        return lapsed
    }

    /** Queues giving up every seat: each processing list goes back to the head of its input. */
    fun releaseAll(pipeline: Pipeline) {
        val all = seats.values.toList()
        seats.clear()
        for ((seat, counted) in all) {
            val input = keys.serviceInput(seat.service)
            HostingScripts.RELEASE.queue(
                pipeline,
                listOf(seat.fence.lease, seat.processing, keys.serviceHosts(seat.service), input, keys.queuedOf(input)),
                listOf(seat.fence.instance, instanceId, flag(counted)),
            )
        }
    }

    /** Reclaims the seats of the hosts of [service] whose lease is gone; returns the entries moved back. */
    fun reclaimDead(jedis: Jedis, service: String, counted: Boolean): Long {
        val others = jedis.smembers(keys.serviceHosts(service)).map { it.toString(UTF_8) }.filter { it != instance }
        if (others.isEmpty()) return 0
        val pipeline = jedis.pipelined()
        val alive = others.map { pipeline.exists(keys.hostSeatLease(service, it)) }
        pipeline.sync()
        val dead = others.filterIndexed { i, _ -> !alive[i].get() }
        if (dead.isEmpty()) return 0
        val input = keys.serviceInput(service)
        val scriptKeys = arrayListOf(keys.serviceHosts(service), input, keys.queuedOf(input))
        dead.forEach { scriptKeys += keys.hostSeatLease(service, it); scriptKeys += keys.hostProcessing(service, it) }
        val reply = HostingScripts.RECLAIM.run(jedis, scriptKeys, listOf(flag(counted)) + dead.map { it.toByteArray(UTF_8) }) as List<*>
        val hosts = reply[0] as Long
        val moved = reply[1] as Long
        if (hosts > 0) {
            LOG.warn(
                "service '{}': {} host(s) let their lease lapse (died, or frozen or cut off longer than {} ms); {} entr(ies) " +
                    "they had taken and not stored went back to the head of the input",
                service, hosts, leaseTime.toMillis(), moved,
            )
        }
        return moved
    }

    private fun modes(jedis: Jedis, services: List<String>): List<String> {
        val reply = HostingScripts.MODES.run(
            jedis,
            services.map(keys::hostingMode),
            listOf(leaseMillis) + services.map { modeOf(it).name.toByteArray(UTF_8) },
        ) as List<*>
        return reply.map { (it as ByteArray).toString(UTF_8) }
    }

    private companion object {
        val LOG = LoggerFactory.getLogger(SharedHosting::class.java)

        fun flag(on: Boolean): ByteArray = (if (on) "1" else "0").toByteArray(UTF_8)
    }
}

package dev.prime.optimus

import org.slf4j.LoggerFactory
import redis.clients.jedis.exceptions.JedisDataException

/**
 * Warns when the Redis of a core may evict its keys: a Redis with a `maxmemory` and a
 * `maxmemory-policy` other than `noeviction` deletes keys of its choice when it reaches that
 * memory, and Optimus keeps its queues, values in flight and leases in keys.
 *
 * Design note. The check reads `INFO memory` (its fields `maxmemory` and `maxmemory_policy`)
 * rather than `CONFIG GET`, which managed services often disable. It is one command on a session
 * that already reached Redis, sent once per core at start; on a Redis Cluster the session's
 * connection goes to the master of the topology's slot, whose settings are the ones that count.
 * It never fails the start: a refusal (`NOPERM`: the user lacks `info`), a broken connection or a
 * reply without those fields skips it with a DEBUG line.
 */
internal object EvictionCheck {
    private val LOG = LoggerFactory.getLogger(EvictionCheck::class.java)

    /** The policy that never evicts: a Redis with it refuses writes (`OOM`) at its `maxmemory` instead. */
    const val NO_EVICTION: String = "noeviction"

    /**
     * Reads the eviction settings of the Redis [session] talks to, in one round trip bounded by
     * the session's socket timeout, and logs one WARN for core [core] if that Redis may evict keys.
     */
    fun check(session: RedisSession, core: String) {
        val info = try {
            session.readOnce { it.info("memory") }
        } catch (e: Exception) {
            val why = if (e is JedisDataException && RedisPermissions.isRefusal(e)) "its Redis user may not run INFO" else e.toString()
            LOG.debug("core '{}' did not check whether Redis may evict its keys: {}", core, why)
            return
        }
        val settings = settingsOf(info)
        if (settings == null) {
            LOG.debug("core '{}' did not check whether Redis may evict its keys: INFO memory has no maxmemory fields", core)
            return
        }
        warning(core, settings.first, settings.second)?.let { LOG.warn(it) }
    }

    /** `maxmemory` (bytes) and `maxmemory_policy` from the text of `INFO memory`, or `null` if either is missing. */
    fun settingsOf(info: String): Pair<Long, String>? {
        var maxmemory: Long? = null
        var policy: String? = null
        for (line in info.lineSequence()) {
            val field = line.trim()
            when {
                field.startsWith("maxmemory:") -> maxmemory = field.substringAfter(':').toLongOrNull()
                field.startsWith("maxmemory_policy:") -> policy = field.substringAfter(':')
            }
        }
        return if (maxmemory == null || policy.isNullOrEmpty()) null else maxmemory to policy
    }

    /**
     * The WARN line for core [core] on a Redis with [maxmemory] bytes and [policy], or `null` if that
     * Redis evicts nothing (no `maxmemory`, or `noeviction`).
     */
    fun warning(core: String, maxmemory: Long, policy: String): String? {
        if (maxmemory == 0L || policy == NO_EVICTION) return null
        val loses = when {
            policy.startsWith("allkeys-") ->
                "it may delete any key of the topology: service queues, values in flight and unread values are lost"
            policy.startsWith("volatile-") ->
                "it may delete the keys that have an expiry, which are the leases: a live instance or host is then taken " +
                    "for dead (its reader lists are reclaimed, unread values lost, and another process takes over its " +
                    "services), and reply lists (calls in flight time out)"
            else -> "it may delete keys of the topology, and what they hold is lost"
        }
        return "core '$core': Redis may evict keys: maxmemory-policy is $policy with maxmemory $maxmemory bytes, so when " +
            "Redis reaches that memory $loses. Set maxmemory-policy noeviction (a full Redis then refuses writes instead " +
            "of deleting keys): CONFIG SET maxmemory-policy noeviction, or the maxmemory-policy parameter of a managed service"
    }
}

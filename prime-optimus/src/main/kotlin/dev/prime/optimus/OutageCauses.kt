package dev.prime.optimus

import redis.clients.jedis.exceptions.JedisDataException

/**
 * The causes one outage of a retrying loop (a service's, the heartbeat's) has logged, so that the
 * loop says why it fails once, and once more for each other cause the same outage meets (the
 * connection lost, then Redis refusing new connections at its `maxclients`), not at every attempt.
 *
 * Design note. A cause is the kind of failure, not its text: a lost connection (any [RedisConnections.isTransient]
 * failure), a connection refused at `maxclients` ([TooManyClients]), or an error Redis answered, by
 * its code (`OOM`, `NOPERM`, ...); anything else by its class. An outage meets few kinds, so the set
 * stays small. Not thread-safe: each loop has its own.
 */
internal class OutageCauses {
    private val logged = HashSet<String>()

    /** Whether the loop is between a failure and its next success. */
    private val inOutage: Boolean get() = logged.isNotEmpty()

    /** Records [e]'s cause; whether this outage had not met it yet (then log it). */
    fun isNew(e: Throwable): Boolean = logged.add(kind(e))

    /** The loop succeeded: the outage, if any, is over; whether there was one. */
    fun end(): Boolean = inOutage.also { logged.clear() }

    private fun kind(e: Throwable): String = when {
        e is TooManyClients -> "maxclients"
        e is Exception && RedisConnections.isTransient(e) -> "lost"
        e is JedisDataException -> "error " + e.message.orEmpty().substringBefore(' ')
        else -> e.javaClass.name
    }
}

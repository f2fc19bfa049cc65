package dev.prime.optimus

import dev.prime.PrimeException
import redis.clients.jedis.exceptions.JedisDataException

/**
 * Turns Redis ACL refusals (`NOPERM`) into a message a user can act on: which command or key the
 * Redis user lacks, and where the list of what Optimus needs is.
 */
internal object RedisPermissions {
    /** The ACL commands Optimus needs; kept equal to the list in docs/architecture.md. */
    const val NEEDED: String = "blmove, client|setname, del, eval, evalsha, exec, exists, get, hdel, hello, hgetall, hlen, " +
        "hset, incr, incrby, info, lindex, llen, lmove, lpop, lrange, lrem, lset, ltrim, multi, pexpire, ping, pttl, rpush, sadd, scard, " +
        "select (with a database other than 0), set, sismember, smembers, srem, type, unwatch and watch"

    private val COMMAND = Regex("run the '([^']+)' command")

    fun isRefusal(e: Throwable): Boolean {
        val message = e.message ?: return false
        return e is JedisDataException && ("NOPERM" in message || "no permissions" in message.lowercase())
    }

    /** A [PrimeException] explaining [e] (a refusal, see [isRefusal]) met while doing [what]. */
    fun explain(e: JedisDataException, user: String?, topology: String, what: String): PrimeException {
        val who = if (user == null) "the default Redis user" else "the Redis user '$user'"
        val command = COMMAND.find(e.message ?: "")?.groupValues?.get(1)
        val lacks = if (command != null) {
            "lacks the command '$command' (grant it: ACL SETUSER ${user ?: "default"} +$command)"
        } else {
            "lacks access to a key of topology '$topology' (grant the key pattern prime:{$topology}:*)"
        }
        return PrimeException(
            "$what was refused: $who $lacks. Optimus needs the commands $NEEDED, on keys prime:{$topology}:* " +
                "(see \"Redis permissions\" in docs/architecture.md). Redis said: ${e.message}",
            e,
        )
    }
}

package dev.prime.optimus

import dev.prime.PrimeException
import redis.clients.jedis.Protocol
import redis.clients.jedis.exceptions.JedisDataException

/**
 * Refuses to start a core on a Redis that lacks `LMOVE` or `BLMOVE` (added in Redis 6.2; a
 * server may also have them renamed or disabled): every service, call and reader of Optimus moves
 * values with them, and without them services log "cannot read its input" and retry forever,
 * calls and reads fail with Redis's bare "unknown command".
 *
 * Design note. The check is one round trip: `MULTI`, `LMOVE` and `BLMOVE` of [Keys.commandProbe]
 * (a list that never exists, so nothing moves and, inside a transaction, `BLMOVE` does not
 * block), `EXEC`. A command Redis does not know is refused when it is queued, with "unknown
 * command". Only that answer fails the start; any other (a user refused a command, `NOPERM`,
 * which the command's first use explains; a broken connection) skips the check, as
 * [EvictionCheck] does. It only reads, so it waits for no replica.
 */
internal object CommandCheck {
    /** The commands checked, in the order they are sent after `MULTI`. */
    private val CHECKED = listOf("LMOVE", "BLMOVE")

    /**
     * Sends the check on [session] for core [core] (whose probe key is in [keys]).
     *
     * @throws PrimeException naming the missing command and "Redis 6.2 or newer" if Redis does not know one
     */
    fun check(session: RedisSession, keys: Keys, core: String, redis: String) {
        val answers = try {
            session.readOnce { jedis ->
                val connection = jedis.connection
                val probe = keys.commandProbe
                connection.sendCommand(MULTI)
                connection.sendCommand(commandOf(Protocol.Command.LMOVE, probe, probe, LEFT, LEFT))
                connection.sendCommand(commandOf(Protocol.Command.BLMOVE, probe, probe, LEFT, LEFT, "0.001".toByteArray()))
                connection.sendCommand(EXEC)
                connection.getMany(4)
            }
        } catch (_: Exception) {
            return // out of reach now: the core's first real command says so
        }
        for ((i, command) in CHECKED.withIndex()) {
            val answer = answers[i + 1]
            if (answer is JedisDataException && answer.message?.lowercase()?.contains("unknown command") == true) {
                throw PrimeException(
                    "core '$core' cannot run on the Redis at $redis: it does not know the command $command (Redis said: " +
                        "${answer.message}). Optimus moves values with LMOVE and BLMOVE: it needs Redis 6.2 or newer " +
                        "with both commands enabled (not renamed by rename-command)",
                    answer,
                )
            }
        }
    }
}

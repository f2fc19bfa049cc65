package dev.prime.optimus

import redis.clients.jedis.Jedis
import redis.clients.jedis.exceptions.JedisNoScriptException
import java.nio.charset.StandardCharsets.UTF_8
import java.security.MessageDigest

/**
 * The Lua scripts that make each step of a service one atomic operation in Redis.
 *
 * [STEP] does, in order and atomically: push values to lists (the next service's input, reply
 * lists, dead letters), publish values to a source (its log and every registered reader list,
 * each trimmed to the retention, counting what a reader lost), acknowledge the first `ack`
 * entries of a processing list, and move up to `take` new entries from an input list to that
 * processing list, returning them. A crash between any two steps therefore neither loses a value
 * (it stays in the processing list until its results are stored) nor duplicates one. Values for
 * the same list go in one `RPUSH` (up to 1000 at a time), not one call each: a command called
 * from Lua costs about as much as storing a small value. Entries are taken with `LMOVE`, one at a
 * time, which moves the stored string itself (`LRANGE` + `RPUSH` copied each one into Lua and back).
 *
 * [REGISTER] adds a reader list to a source; a reader that is new gets a copy of the retained
 * values (a reader starts at the oldest retained value).
 *
 * Scripts run with EVALSHA and fall back to EVAL when the server does not know them (after a
 * restart), which also loads them.
 */
internal class Script private constructor(private val source: ByteArray) {
    private val sha: ByteArray = MessageDigest.getInstance("SHA-1").digest(source)
        .joinToString("") { "%02x".format(it) }.toByteArray(UTF_8)

    fun run(jedis: Jedis, keys: List<ByteArray>, args: List<ByteArray>): Any? = try {
        jedis.evalsha(sha, keys, args)
    } catch (_: JedisNoScriptException) {
        jedis.eval(source, keys, args)
    }

    companion object {
        /** KEYS: processing, input, source log, source readers. ARGV: ack, take, retention, pushes, (key, value) x pushes, published values... */
        val STEP = Script(
            """
            local proc, input, log, readers = KEYS[1], KEYS[2], KEYS[3], KEYS[4]
            local ack, take, retention, pushes = tonumber(ARGV[1]), tonumber(ARGV[2]), tonumber(ARGV[3]), tonumber(ARGV[4])
            local i = 5
            local last = 4 + 2 * pushes
            while i <= last do
              local key, values = ARGV[i], {ARGV[i + 1]}
              i = i + 2
              while i <= last and ARGV[i] == key and #values < 1000 do
                values[#values + 1] = ARGV[i + 1]
                i = i + 2
              end
              redis.call('RPUSH', key, unpack(values))
            end
            if i <= #ARGV then
              local targets = redis.call('SMEMBERS', readers)
              for start = i, #ARGV, 1000 do
                local stop = math.min(start + 999, #ARGV)
                redis.call('RPUSH', log, unpack(ARGV, start, stop))
                for _, target in ipairs(targets) do
                  redis.call('RPUSH', target, unpack(ARGV, start, stop))
                end
              end
              redis.call('LTRIM', log, -retention, -1)
              for _, target in ipairs(targets) do
                local length = redis.call('LLEN', target)
                if length > retention then
                  redis.call('LTRIM', target, length - retention, -1)
                  redis.call('INCRBY', target .. ':missed', length - retention)
                end
              end
            end
            if ack > 0 then
              redis.call('LTRIM', proc, ack, -1)
            end
            if take > 0 then
              local taken = {}
              for k = 1, take do
                local value = redis.call('LMOVE', input, proc, 'LEFT', 'RIGHT')
                if not value then
                  break
                end
                taken[k] = value
              end
              return taken
            end
            return {}
            """.trimIndent().toByteArray(UTF_8),
        )

        /** KEYS: source readers, source log, reader list. Returns 1 if the reader is new. */
        val REGISTER = Script(
            """
            if redis.call('SADD', KEYS[1], KEYS[3]) == 0 then
              return 0
            end
            local retained = redis.call('LRANGE', KEYS[2], 0, -1)
            for start = 1, #retained, 1000 do
              redis.call('RPUSH', KEYS[3], unpack(retained, start, math.min(start + 999, #retained)))
            end
            return 1
            """.trimIndent().toByteArray(UTF_8),
        )
    }
}

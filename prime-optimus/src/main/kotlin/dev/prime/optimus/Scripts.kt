package dev.prime.optimus

import redis.clients.jedis.CommandArguments
import redis.clients.jedis.Jedis
import redis.clients.jedis.Pipeline
import redis.clients.jedis.Protocol
import redis.clients.jedis.exceptions.JedisNoScriptException
import java.nio.charset.StandardCharsets.UTF_8
import java.security.MessageDigest

/**
 * The Lua scripts that make each step of a service one atomic operation in Redis.
 *
 * Entries are single envelopes or [Frame]s (many values in one entry). Queue counts and
 * retention are in values: a service's input has a count of the values it holds
 * (`<input>:queued`, a frame counts its values, a caller's request nothing), raised by every push
 * and lowered by every take, which the queue limit is checked against; a source numbers its
 * values (`src:<source>:seq`) and keeps, beside its log, a list of each log entry's first value
 * number and count (`src:<source>:log:numbers`, [SourceKeys.numbers]). A plain reader's list holds
 * the newest entries of the log (it registered with a copy of the log, gets every later frame, and
 * takes from its head), so the log and every reader are trimmed by value numbers, whole frames at
 * a time, reading only those small numbers: a frame is stored as it came and never copied into
 * Lua again to be renumbered or to read its head.
 *
 * [STEP] does, in order and atomically: check that this instance still holds the service's host
 * lease (else it answers `FENCED` and changes nothing: a host frozen past its lease must not store
 * the step it was in, whose acknowledgement would trim its successor's processing list); check
 * that the caller's view of the output source's readers is current (else it answers `STALE` and
 * changes nothing) and that the service queues it feeds have room, by their counts (else `FULL`,
 * nothing changed); push entries to the next service's input; publish frames to a source
 * (numbered; its log and every plain reader list, each trimmed to the newest `retention` values
 * plus at most the rest of the oldest frame kept, counting what a reader lost in values, and every
 * service input, never trimmed: a service's input is a queue); push replies, each only after
 * checking that its key is in this topology's reply namespace and a list (a reply list gets an
 * expiry; a bad one is dead-lettered instead); push dead letters and trim the dead-letter list to
 * its cap, counting what it trimmed; acknowledge the first `ack` entries of a processing list (a
 * frame is acknowledged whole); and move new entries from an input list to that processing list,
 * until they hold `take` values or reach `takeBytes` (always at least one entry), returning them
 * (an entry above `maxBytes` comes back as its size and a prefix, not the blob). A crash between
 * any two steps therefore neither loses a value (it stays in the processing list until its
 * results are stored) nor duplicates one. Values for the same list go in one `RPUSH` (up to 1000
 * at a time), not one call each: a command called from Lua costs about as much as storing a small
 * value. Entries are taken with `LMOVE`, one at a time, which moves the stored string itself.
 *
 * Every key a script touches is passed in KEYS (Redis Cluster and Redis-compatible servers need
 * that): the caller passes the reader and service lists it knows, and the script checks them
 * against the source's two sets (plain readers, service inputs) before it writes anything.
 *
 * [PEEK] reads the head of a processing list under the same bounds, fenced like [STEP] (after a
 * restart, and after every idle wait: a host that resumes from a freeze learns there that it lost
 * its lease before it takes anything more; the blocking take, `BLMOVE`, cannot run in a script,
 * so [COUNT_IDLE_TAKE], pipelined behind it, lowers the queue count by what it took).
 *
 * [REQUEST_STEP] is the step of a service only called (its input holds callers' requests, one
 * value per entry, and keeps no queue count) that handled one request into one result, when the
 * take of that request was not watched for a step without a script ([RequestStep.storeWatched]:
 * a backlog, or the first take after a refused transaction): the reply
 * (or, in a chain, the request for the next service), pushed, fenced and acknowledged like [STEP]
 * does it, with the same take; it carries 4 keys and 8 arguments where [STEP] carries 13 and 24,
 * and runs a handful of commands, so a call's step costs Redis about half as much. Anything it
 * cannot do (a reply key it refuses) it leaves untouched for [STEP].
 *
 * [REGISTER] adds a reader or service list to a source's set; a list that is new gets a copy of
 * the retained values (it starts at the oldest retained value; a service input's count grows by them).
 *
 * Scripts run with EVALSHA and fall back to EVAL when the server does not know them (after a
 * restart), which also loads them. The liveness scripts ([LeaseScripts]) run the same way.
 */
internal class Script(text: String) {
    private val source: ByteArray = text.trimIndent().toByteArray(UTF_8)
    private val sha: ByteArray = MessageDigest.getInstance("SHA-1").digest(source)
        .joinToString("") { "%02x".format(it) }.toByteArray(UTF_8)

    /** Runs the script (EVALSHA, or EVAL when the server does not know it yet, which also loads it). */
    fun run(jedis: Jedis, keys: List<ByteArray>, args: List<ByteArray>): Any? = try {
        jedis.connection.executeCommand(command(Protocol.Command.EVALSHA, sha, keys, args))
    } catch (_: JedisNoScriptException) {
        jedis.connection.executeCommand(command(Protocol.Command.EVAL, source, keys, args))
    }

    /**
     * Runs the script as EVAL, sending its text: one round trip even when the server does not
     * know it yet, for a rare script that must finish within a tight bound.
     */
    fun runText(jedis: Jedis, keys: List<ByteArray>, args: List<ByteArray>): Any? = jedis.eval(source, keys, args)

    /** Queues the script in [pipeline] (as EVAL: a pipeline cannot fall back). */
    fun queue(pipeline: Pipeline, keys: List<ByteArray>, args: List<ByteArray>) {
        pipeline.eval(source, keys, args)
    }

    /**
     * Queues the script in [pipeline] as EVALSHA (no script text to send and hash on every call):
     * the caller reads its [redis.clients.jedis.Response] and, on [JedisNoScriptException] (the
     * server restarted), runs the script again with [run], which loads it.
     */
    fun queueBySha(pipeline: Pipeline, keys: List<ByteArray>, args: List<ByteArray>): redis.clients.jedis.Response<Any?> =
        pipeline.evalsha(sha, keys, args)

    /**
     * Writes the script's EVALSHA to [connection] without reading its answer (the caller sends
     * more commands behind it and reads the answers in order; on [JedisNoScriptException] it runs
     * the script again with [run], which loads it).
     */
    fun send(connection: redis.clients.jedis.Connection, keys: List<ByteArray>, args: List<ByteArray>) {
        connection.sendCommand(command(Protocol.Command.EVALSHA, sha, keys, args))
    }

    /**
     * `EVALSHA`/`EVAL` of [keys] and [args] with no argument copied ([SentAsIs]): Jedis's own
     * `evalsha` copies every argument, and a step's arguments are mostly its frames. Its answer
     * is what Jedis's `evalsha` returns (the raw reply). The lists must not change while it is sent.
     */
    private fun command(name: Protocol.Command, script: ByteArray, keys: List<ByteArray>, args: List<ByteArray>): CommandArguments {
        val command = commandOf(name, script, keys.size.toString().toByteArray(UTF_8))
        for (key in keys) command.add(SentAsIs(key))
        for (arg in args) command.add(SentAsIs(arg))
        return command
    }

    companion object {
        /**
         * KEYS: 1 processing, 2 input, 3 dead letters, 4 dead letters trimmed (a counter), 5 next
         * service's input, 6 source log, 7 source reader set, 8 source service set, 9 the service's
         * host lease (any existing key when ARGV 18 is empty), 10 the source's value counter, 11
         * the input's queue count (when ARGV 20 is 1), 12 the next input's queue count, 13 the
         * numbers of the source log's entries ([SourceKeys.numbers]), then the reply keys, the
         * reader lists, their missed counters, the service inputs, their queue counts.
         * ARGV: 1-17 the counts and limits (see [StepBatch.execute]; 17 is the number of published
         * frames), 18 the instance id that must hold the host lease (empty: no fence, for readers
         * and publishers), 19 the published values, 20 '1' if the input's queue count is kept (a
         * service), 21 what the entries pushed to the next service add to its count, then the
         * per-service queue limits and the entries. Returns `{'OK', missed per reader, taken...}`, `{'STALE'}`,
         * `{'FULL', key, length, limit}` or `{'FENCED', holder}` (the host lease is held by
         * another instance, or by none: empty; nothing was written), or, for a fenced step that
         * takes, `{'STRAY'}` when the processing list holds other than just the `ack` entries the
         * service handled (nothing was written: see [StageService]).
         */
        val STEP = Script(
            """
            local proc, input, dead, deadTrimmed, nextKey, log, readers, services, hostLease, sequence, queued, nextQueued =
              KEYS[1], KEYS[2], KEYS[3], KEYS[4], KEYS[5], KEYS[6], KEYS[7], KEYS[8], KEYS[9], KEYS[10], KEYS[11], KEYS[12]
            local numbers = KEYS[13]
            local ack, take, takeBytes, maxBytes = tonumber(ARGV[1]), tonumber(ARGV[2]), tonumber(ARGV[3]), tonumber(ARGV[4])
            local retention, deadLimit, nextLimit, strict = tonumber(ARGV[5]), tonumber(ARGV[6]), tonumber(ARGV[7]), ARGV[8] == '1'
            local replyPrefix, replyTtl = ARGV[9], ARGV[10]
            local nReplyKeys, nReaders, nServices = tonumber(ARGV[11]), tonumber(ARGV[12]), tonumber(ARGV[13])
            local nNext, nReplies, nDead, nPublished = tonumber(ARGV[14]), tonumber(ARGV[15]), tonumber(ARGV[16]), tonumber(ARGV[17])
            local fence, publishedValues = ARGV[18], tonumber(ARGV[19])
            local counted, nextValues = ARGV[20] == '1', tonumber(ARGV[21])
            if fence ~= '' then
              local holder = redis.call('GET', hostLease)
              if holder ~= fence then return {'FENCED', holder or ''} end
              -- a service that takes holds the whole processing list (what it acknowledges now): more is an entry
              -- another connection moved there (an earlier host's blocking take), which the service must read first
              if take > 0 and redis.call('LLEN', proc) ~= ack then return {'STRAY'} end
            end
            local readerAt = 13 + nReplyKeys
            local missedAt = readerAt + nReaders
            local serviceAt = missedAt + nReaders
            local serviceQueuedAt = serviceAt + nServices
            local limitsAt = 21
            local nextAt = limitsAt + nServices
            local repliesAt = nextAt + nNext
            local deadAt = repliesAt + 3 * nReplies
            local publishedAt = deadAt + nDead
            local function pushAll(key, values, from, count)
              local length = 0
              for start = from, from + count - 1, 1000 do
                length = redis.call('RPUSH', key, unpack(values, start, math.min(start + 999, from + count - 1)))
              end
              return length
            end
            if nPublished > 0 then
              if redis.call('SCARD', readers) ~= nReaders or redis.call('SCARD', services) ~= nServices then
                return {'STALE'}
              end
              for r = 1, nReaders do
                if redis.call('SISMEMBER', readers, KEYS[readerAt + r]) == 0 then return {'STALE'} end
              end
              for s = 1, nServices do
                local key = KEYS[serviceAt + s]
                if redis.call('SISMEMBER', services, key) == 0 then return {'STALE'} end
                local limit, length = tonumber(ARGV[limitsAt + s]), tonumber(redis.call('GET', KEYS[serviceQueuedAt + s]) or '0')
                if (strict and length + publishedValues > limit) or ((not strict) and length >= limit) then
                  return {'FULL', key, length, limit}
                end
              end
            end
            if nNext > 0 then
              local length = tonumber(redis.call('GET', nextQueued) or '0')
              if nextLimit > 0 and length >= nextLimit then return {'FULL', nextKey, length, nextLimit} end
              pushAll(nextKey, ARGV, nextAt + 1, nNext)
              if nextValues > 0 then redis.call('INCRBY', nextQueued, nextValues) end
            end
            local missed = {}
            if nPublished > 0 then
              -- number the values: the log's side list (numbers) holds each log entry's first value number and count
              local last = redis.call('INCRBY', sequence, publishedValues)
              local keepFrom = last - retention + 1
              local at = last - publishedValues + 1
              local numbered = {}
              for k = 1, nPublished do
                local n = struct.unpack('>I4', ARGV[publishedAt + k], 11)
                numbered[k] = struct.pack('>I8I4', at, n)
                at = at + n
              end
              pushAll(log, ARGV, publishedAt + 1, nPublished)
              pushAll(numbers, numbered, 1, nPublished)
              for s = 1, nServices do
                pushAll(KEYS[serviceAt + s], ARGV, publishedAt + 1, nPublished)
                redis.call('INCRBY', KEYS[serviceQueuedAt + s], publishedValues)
              end
              -- the log's entries whose values are all older than keepFrom: how many, and their values one by one
              local numberedEntries, logLength = redis.call('LLEN', numbers), redis.call('LLEN', log)
              if numberedEntries > logLength then
                -- numbers of entries the log no longer holds (it was deleted or trimmed outside these scripts)
                redis.call('LTRIM', numbers, numberedEntries - logLength, -1)
                numberedEntries = logLength
              end
              local stale, staleValues = 0, {}
              while stale < numberedEntries do
                local first, n = struct.unpack('>I8I4', redis.call('LINDEX', numbers, stale))
                if first + n > keepFrom then break end
                stale = stale + 1
                staleValues[stale] = n
              end
              -- entries without a number (none unless Redis lost the numbers) are older than every numbered one:
              -- dropped (their values counted) once the numbered entries alone hold the retention
              local function dropUnnumbered(key, extra)
                local dropped = 0
                if extra <= 0 or numberedEntries == 0 then return 0 end
                local first = struct.unpack('>I8', redis.call('LINDEX', numbers, 0))
                if first > keepFrom then return 0 end
                for _ = 1, extra do
                  local head = redis.call('LPOP', key)
                  if #head >= 14 and string.byte(head, 1) == 70 then dropped = dropped + struct.unpack('>I4', head, 11)
                  else dropped = dropped + 1 end
                end
                return dropped
              end
              for r = 1, nReaders do
                -- a reader list holds the newest entries of the log (it took its oldest ones away)
                local key = KEYS[readerAt + r]
                pushAll(key, ARGV, publishedAt + 1, nPublished)
                local length = redis.call('LLEN', key)
                local over = dropUnnumbered(key, length - numberedEntries)
                local skipped = numberedEntries - math.min(length, numberedEntries)
                local drop = stale - skipped
                if drop > 0 then
                  redis.call('LTRIM', key, drop, -1)
                  for k = skipped + 1, stale do over = over + staleValues[k] end
                end
                if over > 0 then redis.call('INCRBY', KEYS[missedAt + r], over) end
                missed[r] = over
              end
              dropUnnumbered(log, logLength - numberedEntries)
              if stale > 0 then
                redis.call('LTRIM', log, stale, -1)
                redis.call('LTRIM', numbers, stale, -1)
              end
            end
            local refused = {}
            for k = 0, nReplies - 1 do
              local at = repliesAt + 1 + 3 * k
              local key = KEYS[13 + tonumber(ARGV[at])]
              local reason = nil
              if string.sub(key, 1, #replyPrefix) ~= replyPrefix then
                reason = "outside this topology's reply namespace " .. replyPrefix .. '*'
              else
                local kind = redis.call('TYPE', key)['ok']
                if kind ~= 'list' and kind ~= 'none' then reason = 'of type ' .. kind .. ', not a reply list' end
              end
              if reason then
                local text = 'refused request: its reply key ' .. string.sub(key, 1, 200) .. ' is ' .. reason
                local raw = redis.call('LINDEX', proc, tonumber(ARGV[at + 1])) or ''
                refused[#refused + 1] = struct.pack('>I4', #text) .. text .. raw
              else
                redis.call('RPUSH', key, ARGV[at + 2])
                redis.call('PEXPIRE', key, replyTtl)
              end
            end
            if nDead > 0 or #refused > 0 then
              local length = 0
              if nDead > 0 then length = pushAll(dead, ARGV, deadAt + 1, nDead) end
              if #refused > 0 then length = redis.call('RPUSH', dead, unpack(refused)) end
              if length > deadLimit then
                redis.call('LTRIM', dead, length - deadLimit, -1)
                redis.call('INCRBY', deadTrimmed, length - deadLimit)
              end
            end
            if ack > 0 then
              redis.call('LTRIM', proc, ack, -1)
            end
            local result = {'OK', missed}
            local bytes, values, taken, drained = 0, 0, 0, false
            while values < take do
              if bytes >= takeBytes then break end
              local value = redis.call('LMOVE', input, proc, 'LEFT', 'RIGHT')
              if not value then
                drained = true
                break
              end
              bytes = bytes + #value
              if #value >= 14 and string.byte(value, 1) == 70 then
                local n = struct.unpack('>I4', value, 11)
                taken = taken + n
                values = values + math.max(1, n)
              else
                if #value >= 10 and string.byte(value, 1) == 80 and string.byte(value, 2) == 0 then taken = taken + 1 end
                values = values + 1
              end
              if #value > maxBytes then value = {#value, string.sub(value, 1, 1024)} end
              result[#result + 1] = value
            end
            if counted then
              if drained then
                redis.call('DEL', queued) -- the input is empty: nothing is queued, whatever the count said
              elseif taken > 0 and redis.call('INCRBY', queued, -taken) < 0 then
                redis.call('DEL', queued) -- entries nobody counted (pushed from outside): never below zero
              end
            end
            return result
            """,
        )

        /**
         * KEYS: processing, the service's host lease. ARGV: most entries, most bytes, largest
         * entry, the instance id that must hold the host lease, the lease time in ms with which
         * to claim the lease if nobody holds it (empty: never claim). Returns `{complete (1: the
         * whole list was returned), entries...}`, entries above the largest size as `{size,
         * prefix}`, or `{'FENCED', holder}` as [STEP] does. The claim is the only one of a running
         * service's lapsed lease (the heartbeat only renews: [LeaseScripts.HOST_RENEW]), so every
         * step after it stores a batch read after it, never one read before the lapse, when
         * another host may have held the lease and left entries in the list.
         */
        val PEEK = Script(
            """
            local holder = redis.call('GET', KEYS[2])
            if not holder and ARGV[5] ~= '' then
              redis.call('SET', KEYS[2], ARGV[4], 'PX', ARGV[5])
              holder = ARGV[4]
            end
            if holder ~= ARGV[4] then return {'FENCED', holder or ''} end
            local count, takeBytes, maxBytes = tonumber(ARGV[1]), tonumber(ARGV[2]), tonumber(ARGV[3])
            local length = redis.call('LLEN', KEYS[1])
            local result = {0}
            local bytes, values = 0, 0
            for k = 0, length - 1 do
              if bytes >= takeBytes or values >= count then return result end
              local value = redis.call('LINDEX', KEYS[1], k)
              bytes = bytes + #value
              if #value >= 14 and string.byte(value, 1) == 70 then
                values = values + math.max(1, struct.unpack('>I4', value, 11))
              else
                values = values + 1
              end
              if #value > maxBytes then value = {#value, string.sub(value, 1, 1024)} end
              result[#result + 1] = value
            end
            if #result - 1 == length then result[1] = 1 end
            return result
            """,
        )

        /**
         * Right after an idle `BLMOVE` of a service (queued behind it in one pipeline): if the
         * processing list holds just the entry it moved, takes that entry's values off the
         * input's queue count, as [STEP] does for what it takes. KEYS: processing, queue count.
         */
        val COUNT_IDLE_TAKE = Script(
            """
            if redis.call('LLEN', KEYS[1]) ~= 1 then return 0 end
            local entry = redis.call('LINDEX', KEYS[1], 0)
            local n = 0
            if #entry >= 14 and string.byte(entry, 1) == 70 then n = struct.unpack('>I4', entry, 11)
            elseif #entry >= 10 and string.byte(entry, 1) == 80 and string.byte(entry, 2) == 0 then n = 1 end
            if n > 0 and redis.call('INCRBY', KEYS[2], -n) < 0 then redis.call('DEL', KEYS[2]) end
            return n
            """,
        )

        /**
         * A service's queue depth in values, for metrics: its input's queue count (or, for a
         * service only called, its input's length: one request per entry) plus the values of the
         * entries in its processing list (and in those of the hosts of an unordered service), summed
         * here so no frame travels to the client. KEYS: input, processing, queue count, then any
         * further processing lists.
         */
        val QUEUE_DEPTH = Script(
            """
            local waiting = tonumber(redis.call('GET', KEYS[3]) or redis.call('LLEN', KEYS[1]))
            local held = 0
            for k = 2, #KEYS do
              if k ~= 3 then
                for _, entry in ipairs(redis.call('LRANGE', KEYS[k], 0, -1)) do
                  if #entry >= 14 and string.byte(entry, 1) == 70 then held = held + struct.unpack('>I4', entry, 11)
                  else held = held + 1 end
                end
              end
            end
            return math.max(0, waiting) + held
            """,
        )

        /**
         * KEYS: the source's reader or service set, source log, the list, and for a service's input
         * its count of queued values, for a plain reader its missed counter. ARGV: '1' for a
         * service's input (the count is kept), '0' for a plain reader (a missed counter a reclaim
         * left with an expiry is kept: see [LeaseScripts.RECLAIM]). Returns 1 if the list is new.
         */
        val REGISTER = Script(
            """
            if redis.call('SADD', KEYS[1], KEYS[3]) == 0 then
              return 0
            end
            local retained = redis.call('LRANGE', KEYS[2], 0, -1)
            for start = 1, #retained, 1000 do
              redis.call('RPUSH', KEYS[3], unpack(retained, start, math.min(start + 999, #retained)))
            end
            if ARGV[1] == '1' then
              local values = 0
              for k = 1, #retained do
                local entry = retained[k]
                if #entry >= 14 and string.byte(entry, 1) == 70 then values = values + struct.unpack('>I4', entry, 11)
                elseif #entry >= 10 and string.byte(entry, 1) == 80 and string.byte(entry, 2) == 0 then values = values + 1 end
              end
              if values > 0 then redis.call('INCRBY', KEYS[4], values) end
            else
              -- a SET without an expiry keeps the count for good (no PERSIST: one command fewer to grant)
              local missed = redis.call('GET', KEYS[4])
              if missed then redis.call('SET', KEYS[4], missed) end
            end
            return 1
            """,
        )

        /**
         * The step of a service only called, for one request with one result (see the class
         * note). KEYS: 1 processing, 2 input, 3 the service's host lease, 4 where the result goes
         * (the caller's reply list, or the next service's input). ARGV: 1 the instance id that
         * must hold the host lease, 2 the entry to push, 3 '1' if it is a reply (checked to be in
         * the reply namespace [4] and a list, then given the expiry [5] in ms), 6 the most entries
         * to take, 7 the bytes after which to stop taking, 8 the largest entry returned whole.
         * In order and atomically: the fence (`{'FENCED', holder}`, nothing written), for a step
         * that takes a processing list of just the request (else `{'STRAY'}`, nothing written), the push
         * (a reply key outside the namespace or holding another type: `{'REFUSED'}`, nothing
         * written, for [STEP] to dead-letter the request), the acknowledgement of the request
         * (the head of the processing list), then the take as [STEP]'s (each entry one value: a
         * called service's input holds requests). Returns `{'OK', taken...}`, an entry above
         * the largest size as `{size, prefix}`. With ARGV 9 '1' a blocking take is queued behind the
         * step (see [RequestStep.executeThenWait]): a take that empties the input puts its last
         * entry back at the input's head, for that blocking take to move instead of waiting.
         */
        val REQUEST_STEP = Script(
            """
            local holder = redis.call('GET', KEYS[3])
            if holder ~= ARGV[1] then return {'FENCED', holder or ''} end
            if tonumber(ARGV[6]) > 0 and redis.call('LLEN', KEYS[1]) ~= 1 then return {'STRAY'} end
            local target = KEYS[4]
            if ARGV[3] == '1' then
              local prefix = ARGV[4]
              if string.sub(target, 1, #prefix) ~= prefix then return {'REFUSED'} end
              local pushed = redis.pcall('RPUSH', target, ARGV[2])
              if type(pushed) == 'table' then return {'REFUSED'} end -- not a list (or Redis refused: STEP says why)
              redis.call('PEXPIRE', target, ARGV[5])
            else
              redis.call('RPUSH', target, ARGV[2])
            end
            redis.call('LTRIM', KEYS[1], 1, -1)
            local result = {'OK'}
            local take, takeBytes, maxBytes = tonumber(ARGV[6]), tonumber(ARGV[7]), tonumber(ARGV[8])
            local bytes = 0
            while #result <= take and bytes < takeBytes do
              local entry = redis.call('LMOVE', KEYS[2], KEYS[1], 'LEFT', 'RIGHT')
              if not entry then break end
              bytes = bytes + #entry
              if #entry > maxBytes then entry = {#entry, string.sub(entry, 1, 1024)} end
              result[#result + 1] = entry
            end
            if ARGV[9] == '1' and #result > 1 and redis.call('LLEN', KEYS[2]) == 0 then
              redis.call('LMOVE', KEYS[1], KEYS[2], 'RIGHT', 'LEFT')
              result[#result] = nil
            end
            return result
            """,
        )
    }
}

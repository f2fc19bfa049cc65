package dev.prime.optimus

/**
 * The scripts of hosting modes and of the seats of [Hosting.UNORDERED] services (see [SharedHosting]).
 *
 * A seat is one host's share of an unordered service: its lease (`svc:<s>:host:<instance>`,
 * holding the token of the host's current run), its processing list (`svc:<s>:proc:<instance>`)
 * and its membership of the service's host set (`svc:<s>:hosts`). Every key is the topology's, so
 * in its hash slot.
 */
internal object HostingScripts {
    /** Moves every entry of `proc` back to the head of `input`, in order; returns the values moved (frames count theirs). */
    private const val MOVE_BACK = """
        local function moveBack(proc, input, queued, counted)
          local values, entries = 0, 0
          while true do
            local entry = redis.call('LMOVE', proc, input, 'RIGHT', 'LEFT')
            if not entry then break end
            entries = entries + 1
            if #entry >= 14 and string.byte(entry, 1) == 70 then values = values + struct.unpack('>I4', entry, 11)
            elseif #entry >= 10 and string.byte(entry, 1) == 80 and string.byte(entry, 2) == 0 then values = values + 1 end
          end
          if counted and values > 0 then redis.call('INCRBY', queued, values) end
          return entries
        end
    """

    /**
     * Declares or renews the hosting modes of services: a mode nobody declared is set, one equal to
     * this process's is renewed, another is left alone. KEYS: the mode keys. ARGV: lease ms, then
     * the modes. Returns, per key, the mode it holds.
     */
    val MODES = Script(
        """
        local result = {}
        for i, key in ipairs(KEYS) do
          local mode = redis.call('GET', key)
          if not mode then
            redis.call('SET', key, ARGV[i + 1], 'PX', ARGV[1])
            mode = ARGV[i + 1]
          elseif mode == ARGV[i + 1] then
            redis.call('PEXPIRE', key, ARGV[1])
          end
          result[i] = mode
        end
        return result
        """,
    )

    /** Takes a seat: KEYS: its lease, the host set. ARGV: the run's token, lease ms, the instance id. */
    val CLAIM = Script(
        """
        redis.call('SET', KEYS[1], ARGV[1], 'PX', ARGV[2])
        redis.call('SADD', KEYS[2], ARGV[3])
        return 1
        """,
    )

    /**
     * Renews seat leases that still hold their run's token (never makes a lapsed one again: its run
     * must start anew). KEYS: the leases. ARGV: lease ms, then the tokens. Returns 1 or 0 per key.
     */
    val RENEW = Script(
        """
        local result = {}
        for i, key in ipairs(KEYS) do
          if redis.call('GET', key) == ARGV[i + 1] then
            redis.call('PEXPIRE', key, ARGV[1])
            result[i] = 1
          else
            result[i] = 0
          end
        end
        return result
        """,
    )

    /**
     * Reclaims the seats of dead hosts: for each candidate still in the host set whose lease is
     * gone, moves its processing list back to the head of the input (raising the queue count by its
     * values) and removes it from the set. KEYS: host set, input, queue count, then per candidate
     * its lease and its processing list. ARGV: '1' if the queue count is kept, then the candidates'
     * instance ids. Returns {hosts reclaimed, entries moved}.
     */
    val RECLAIM = Script(
        MOVE_BACK + """
        local hosts, moved = 0, 0
        for i = 2, #ARGV do
          local lease, proc = KEYS[2 + 2 * (i - 1)], KEYS[3 + 2 * (i - 1)]
          if redis.call('SISMEMBER', KEYS[1], ARGV[i]) == 1 and redis.call('EXISTS', lease) == 0 then
            moved = moved + moveBack(proc, KEYS[2], KEYS[3], ARGV[1] == '1')
            redis.call('SREM', KEYS[1], ARGV[i])
            hosts = hosts + 1
          end
        end
        return {hosts, moved}
        """,
    )

    /**
     * Runs in Redis right after an unordered host's blocking take, written behind it on the same
     * connection, so it runs even if the host dies as soon as Redis answered the take: if the host
     * is no longer in the host set (a survivor reclaimed its seat while the take waited), moves its
     * processing list back to the head of the input (raising the queue count by its values), since
     * no reclaim looks at that list any more. KEYS: host set, the host's processing list, input,
     * queue count. ARGV: the instance id, '1' if the queue count is kept. Returns the entries moved.
     */
    val CHECK_SEATED = Script(
        MOVE_BACK + """
        if redis.call('SISMEMBER', KEYS[1], ARGV[1]) == 1 then return 0 end
        return moveBack(KEYS[2], KEYS[3], KEYS[4], ARGV[2] == '1')
        """,
    )

    /**
     * Gives a seat up (a host that closes): deletes its lease if it still holds the run's token,
     * moves its processing list back to the head of the input and leaves the host set. KEYS: lease,
     * processing list, host set, input, queue count. ARGV: token, instance id, '1' if the queue
     * count is kept. Returns the entries moved.
     */
    val RELEASE = Script(
        MOVE_BACK + """
        if redis.call('GET', KEYS[1]) == ARGV[1] then redis.call('DEL', KEYS[1]) end
        local moved = moveBack(KEYS[2], KEYS[4], KEYS[5], ARGV[3] == '1')
        redis.call('SREM', KEYS[3], ARGV[2])
        return moved
        """,
    )
}

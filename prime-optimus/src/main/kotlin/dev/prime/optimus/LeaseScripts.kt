package dev.prime.optimus

/** The scripts of instance leases, reclaiming and host leases (see [Liveness] and [HostLeases]). */
internal object LeaseScripts {
    /**
     * Renews an instance's lease and reads the topology's epoch, writing ARGV 4 as the epoch if
     * there is none. KEYS: instance lease, instance set, epoch, the instance's declaration count.
     * ARGV: instance id, lease value, lease ms, fresh epoch. Returns {epoch, 1 if the lease was
     * still there else 0, the declaration count or -1 if there is none}.
     */
    val HEARTBEAT = Script(
        """
        local epoch = redis.call('GET', KEYS[3])
        if not epoch then
          redis.call('SET', KEYS[3], ARGV[4])
          epoch = ARGV[4]
        end
        local alive = redis.call('EXISTS', KEYS[1])
        redis.call('SET', KEYS[1], ARGV[2], 'PX', ARGV[3])
        redis.call('SADD', KEYS[2], ARGV[1])
        local declared = redis.call('GET', KEYS[4])
        return {epoch, alive, declared and tonumber(declared) or -1}
        """,
    )

    /** Raises a count to at least ARGV 1. KEYS: the count. */
    val RAISE = Script(
        """
        local current = tonumber(redis.call('GET', KEYS[1]) or '0')
        if current < tonumber(ARGV[1]) then
          redis.call('SET', KEYS[1], ARGV[1])
        end
        return 0
        """,
    )

    /**
     * Removes what a dead instance owned, unless its lease is back (it was only frozen and renewed
     * it). KEYS: its lease, the instance set, its lists hash, its declaration count, then per owned
     * list either 4 keys (reader list, its processing list, its missed counter, the source's reader
     * set) or 1 (a reply list). ARGV: the instance id, how long a reader's missed counter is kept
     * (ms: its process may come back and declare the reader again, which keeps the count: see
     * [Script.REGISTER]), then the key count of each owned list. Returns -1 if the lease is back, 1
     * if the instance is gone entirely, 0 if it still owns lists.
     */
    val RECLAIM = Script(
        """
        if redis.call('EXISTS', KEYS[1]) == 1 then
          return -1
        end
        local k = 5
        for a = 3, #ARGV do
          local n = tonumber(ARGV[a])
          if n == 4 then
            redis.call('SREM', KEYS[k + 3], KEYS[k])
            redis.call('DEL', KEYS[k], KEYS[k + 1])
            redis.call('PEXPIRE', KEYS[k + 2], ARGV[2])
          else
            redis.call('DEL', KEYS[k])
          end
          redis.call('HDEL', KEYS[3], KEYS[k])
          k = k + n
        end
        if redis.call('HLEN', KEYS[3]) == 0 then
          redis.call('DEL', KEYS[3], KEYS[4])
          redis.call('SREM', KEYS[2], ARGV[1])
          return 1
        end
        return 0
        """,
    )

    /**
     * Claims or renews host leases: a lease nobody holds is taken, one this instance holds is
     * renewed, one another holds is left alone. KEYS: host leases. ARGV: instance id, lease ms.
     * Returns, per key, its holder and its remaining milliseconds.
     */
    val HOST_CLAIM = Script(
        """
        local result = {}
        for _, key in ipairs(KEYS) do
          local holder = redis.call('GET', key)
          if not holder then
            redis.call('SET', key, ARGV[1], 'PX', ARGV[2])
            holder = ARGV[1]
          elseif holder == ARGV[1] then
            redis.call('PEXPIRE', key, ARGV[2])
          end
          result[#result + 1] = holder
          result[#result + 1] = redis.call('PTTL', key)
        end
        return result
        """,
    )

    /**
     * Renews the host leases this instance holds; a lease nobody holds is claimed again only where
     * ARGV 3 says so (`1` at the key's place: a service that holds no batch, such as a generic
     * service), else left free (`0`: a service re-claims it as it reads its processing list again:
     * see [Script.PEEK]). KEYS: host leases. ARGV: instance id, lease ms, one `0` or `1` per key.
     * Returns, per key, its holder (empty: nobody) and its remaining milliseconds.
     */
    val HOST_RENEW = Script(
        """
        local result = {}
        for i, key in ipairs(KEYS) do
          local holder = redis.call('GET', key)
          if holder == ARGV[1] then
            redis.call('PEXPIRE', key, ARGV[2])
          elseif not holder and string.sub(ARGV[3], i, i) == '1' then
            redis.call('SET', key, ARGV[1], 'PX', ARGV[2])
            holder = ARGV[1]
          end
          result[#result + 1] = holder or ''
          result[#result + 1] = redis.call('PTTL', key)
        end
        return result
        """,
    )

    /** Deletes the host leases this instance holds. KEYS: host leases. ARGV: instance id. */
    val HOST_RELEASE = Script(
        """
        for _, key in ipairs(KEYS) do
          if redis.call('GET', key) == ARGV[1] then
            redis.call('DEL', key)
          end
        end
        return 0
        """,
    )
}

package dev.prime.optimus

import dev.prime.ServiceGauges
import java.nio.charset.StandardCharsets.UTF_8

/**
 * The queue depth and dead letters of Optimus services for [dev.prime.Metrics], read from Redis
 * when a snapshot is taken: the lengths of the service's input and processing lists (one per host
 * of an unordered service), and of its
 * dead-letter list plus the dead letters trimmed from it (so the count only grows, like the
 * other metrics, until [OptimusCore.clearDeadLetters]).
 *
 * Design note. One Redis connection of its own, used under this object's monitor (snapshots
 * may come from several threads); one attempt per command with the usual command timeout, so a
 * snapshot while Redis is unreachable gives -1 promptly instead of waiting for it.
 */
internal class RedisServiceGauges(private val core: OptimusCore) : ServiceGauges {
    private val session = RedisSession(core.connections)

    /**
     * Waiting in the input list, plus taken into a processing list and not yet stored: in values (a
     * frame holds many). An unordered service's hosts each have a processing list: all are counted.
     */
    override fun queueDepth(service: String): Long = read { jedis ->
        val input = core.keys.serviceInput(service)
        val hosts = jedis.smembers(core.keys.serviceHosts(service)).map { core.keys.hostProcessing(service, it.toString(UTF_8)) }
        val lists = listOf(input, core.keys.serviceProcessing(service), core.keys.queuedOf(input)) + hosts
        Script.QUEUE_DEPTH.run(jedis, lists, emptyList()) as Long
    }

    /** Every Optimus service the core asks about has an input list, read or not. */
    override fun hasQueue(service: String): Boolean = true

    override fun deadLetters(service: String): Long = read { jedis ->
        val kept = jedis.llen(core.keys.deadLetters(service))
        val trimmed = jedis.get(core.keys.deadLettersTrimmed(service))?.toString(UTF_8)?.toLong() ?: 0L
        kept + trimmed
    }

    /** Counted in this process, by its publishes ([ReaderMisses]): no Redis round trip. */
    override fun missed(source: String): Long = core.readerMisses.total(source)

    @Synchronized
    private fun read(op: (redis.clients.jedis.Jedis) -> Long): Long {
        if (core.isClosed) return -1
        return try {
            session.once(op)
        } catch (e: Exception) {
            -1 // Redis unreachable (or the core closing): unknown now
        }
    }
}

package dev.prime.optimus

import org.slf4j.LoggerFactory
import redis.clients.jedis.Jedis
import redis.clients.jedis.params.SetParams
import java.nio.charset.StandardCharsets.UTF_8
import java.util.concurrent.ConcurrentHashMap

/**
 * What one core instance has declared in Redis, and declaring it again after Redis lost it
 * (a [Loss] noticed by the [Liveness] heartbeat).
 *
 * Declared state of an instance: the codec fingerprint (once the core started), the registrations
 * of service inputs with the sources that feed them ([bindings]; every process of the topology
 * makes them, hosting or not), its readers' registrations, its ownership records of reader and
 * reply lists, and the host leases of the services it runs. All of it is idempotent to declare
 * again: a registration that is already there is left alone, and a new one copies the source's
 * retained values into the list (so values published after Redis came back but before this
 * re-declaration reach the reader or service, up to the retention).
 *
 * Design note. Collections are concurrent: declaring threads add to them while the heartbeat
 * thread reads them. An entry is added before it is registered in Redis, so a re-declaration
 * never misses a registration that raced with it (registering twice is harmless).
 */
internal class Redeclaration(
    private val keys: Keys,
    private val coreName: String,
    private val instance: String,
    private val codecFingerprint: String,
    private val hostLeases: HostLeases,
    /** The instance's readers: their sources and lists. */
    private val readers: () -> Collection<Pair<SourceKeys, ByteArray>>,
    /** The instance's reply lists. */
    private val replyLists: () -> List<ByteArray>,
    /** Registers a list with a source: as a service input (a queue) if the flag says so, else as a plain reader. */
    private val register: (Jedis, SourceKeys, ByteArray, Boolean) -> Unit,
    /** Stops a service whose host lease another instance holds now (described). */
    private val lostHosting: (service: String, holder: String) -> Unit,
    /** Renews the hosting modes and the seats of shared services ([SharedHosting]). */
    private val renewShared: (RedisSession) -> Unit = {},
) : LivenessHooks {
    /** Service inputs registered with the sources that feed them. */
    val bindings: MutableSet<Pair<SourceKeys, ByteArray>> = ConcurrentHashMap.newKeySet()

    /** Whether the codec fingerprint was declared (by start()). */
    @Volatile
    var codecDeclared: Boolean = false

    override fun redeclare(session: RedisSession, loss: Loss) {
        val readers = readers().toList()
        val replies = replyLists()
        val bound = bindings.toList()
        val hosted = hostLeases.services.sorted()
        val what = "the codec fingerprint, ${bound.size} service input(s) and ${readers.size} reader(s) registered with " +
            "sources, ${replies.size} reply list(s) and the host lease(s) of $hosted"
        when (loss) {
            Loss.DATA_LOST -> LOG.warn(
                "Redis lost the data of topology '{}' (it restarted without persistence, or failed over to a replica " +
                    "that was behind): values that were only in Redis are gone (queued service inputs, unread reader " +
                    "values, calls waiting for replies, dead letters). Instance {} re-declares {}",
                coreName, instance, what,
            )
            Loss.WRITES_LOST -> LOG.warn(
                "Redis came back behind for topology '{}': it lacks the last declarations of instance {} (a failover to " +
                    "a replica that lagged, or a crash with an append-only file synced every second); the last writes " +
                    "before that are gone (values published, steps stored, registrations made). It re-declares {}",
                coreName, instance, what,
            )
            Loss.LEASE_LAPSED -> LOG.warn(
                "the lease of instance {} of topology '{}' lapsed: this process was frozen or cut off from Redis longer " +
                    "than its lease time, so other processes may have reclaimed its readers and reply lists (values unread " +
                    "in them are gone). It re-declares {}",
                instance, coreName, what,
            )
        }
        session.once { jedis ->
            if (codecDeclared) declareCodec(jedis)
            val lists = keys.instanceLists(instance)
            val pipeline = jedis.pipelined()
            for ((source, list) in readers) pipeline.hset(lists, list, source.readers)
            for (reply in replies) pipeline.hset(lists, reply, EMPTY)
            pipeline.sync()
            for ((source, list) in bound) register(jedis, source, list, true)
            for ((source, list) in readers) register(jedis, source, list, false)
            unregisterClosed(jedis, readers)
        }
        renew(session)
        LOG.info("instance {} of topology '{}' re-declared {}", instance, coreName, what)
    }

    /**
     * Takes back the registrations just made of readers that closed meanwhile: a reader's close
     * forgets it first, then removes its lists, so a close that ran between the snapshot and the
     * registrations may have removed them before they were made again, and nothing else would
     * (every publish would fill the list, and the core's close no longer knows it).
     */
    private fun unregisterClosed(jedis: Jedis, registered: List<Pair<SourceKeys, ByteArray>>) {
        val open = readers().toSet()
        val closed = registered.filter { it !in open }
        if (closed.isEmpty()) return
        val pipeline = jedis.pipelined()
        for ((source, list) in closed) {
            queueReaderRemoval(pipeline, keys, source, list)
            pipeline.hdel(keys.instanceLists(instance), list)
        }
        pipeline.sync()
    }

    override fun renew(session: RedisSession) {
        val taken = session.once(hostLeases::renew)
        for ((service, holder) in taken) lostHosting(service, hostLeases.describe(session, holder))
        renewShared(session)
    }

    private fun declareCodec(jedis: Jedis) {
        jedis.set(keys.codec, codecFingerprint.toByteArray(UTF_8), SetParams().nx())
        val theirs = jedis.get(keys.codec)?.toString(UTF_8)
        if (theirs != codecFingerprint) {
            LOG.error(
                "after Redis lost its data, another process of topology '{}' declared codec fingerprint {} first; this " +
                    "one uses {}: values between them cannot be decoded (they are dead-lettered). Register the same types " +
                    "in the same order in every process",
                coreName, theirs, codecFingerprint,
            )
        }
    }

    private companion object {
        val LOG = LoggerFactory.getLogger(Redeclaration::class.java)
        val EMPTY = ByteArray(0)
    }
}

package dev.prime.optimus

import redis.clients.jedis.util.JedisClusterCRC16
import java.nio.charset.StandardCharsets.UTF_8

/**
 * The Redis keys of one topology. Every key carries the topology in a hash tag (`{topology}`),
 * so all keys of a topology live in one hash slot: the atomic steps (a script that stores a
 * result, publishes it and acknowledges the input) then also run on Redis Cluster. Names are
 * derived only from service and source names, so every process that declares the same topology
 * computes the same keys. On a Redis Cluster the topology therefore lives on the one master that
 * holds its slot ([clusterSlot]); many topologies (one per core name) spread over the masters.
 */
internal class Keys(topology: String) {
    private val prefix = "prime:{$topology}:"

    /**
     * The Redis Cluster hash slot of every key of this topology: the slot of its hash tag, the
     * core name (which holds no brace: letters, digits, `.`, `_`, `-`), so the whole name is the tag.
     */
    fun clusterSlot(): Int = JedisClusterCRC16.getSlot(prefix)

    /** The `SCAN` pattern of every key of the topology (a core name holds no glob character). */
    val all: ByteArray = key("*")

    /** The list a service takes its input from. */
    fun serviceInput(service: String): ByteArray = key("svc:$service:in")

    /** The list holding what a service took and has not yet acknowledged. */
    fun serviceProcessing(service: String): ByteArray = key("svc:$service:proc")

    /** The list of values a service could not process. */
    fun deadLetters(service: String): ByteArray = key("svc:$service:dead")

    /** The retained values of a source (its newest `retention` values). */
    fun sourceLog(source: String): ByteArray = key("src:$source:log")

    /** The number of the last value published to a source (frames in its lists carry their first value's number). */
    fun sourceSequence(source: String): ByteArray = key("src:$source:seq")

    /** The set of plain reader lists a source publishes to (trimmed to its retention). */
    fun sourceReaders(source: String): ByteArray = key("src:$source:readers")

    /** The set of service input lists a source publishes to (queues: never trimmed). */
    fun sourceServices(source: String): ByteArray = key("src:$source:services")

    /** The count of dead letters trimmed from a service's dead-letter list by its cap. */
    fun deadLettersTrimmed(service: String): ByteArray = key("svc:$service:dead:trimmed")

    /** The service whose input list is [input], if it is one of this topology's. */
    fun serviceOf(input: ByteArray): String? {
        val text = input.toString(UTF_8)
        val start = prefix + "svc:"
        return if (text.startsWith(start) && text.endsWith(":in")) text.substring(start.length, text.length - 3) else null
    }

    /** The list of one reader that is not a service. */
    fun reader(id: String): ByteArray = key("rdr:$id")

    /** The processing list that goes with an input or reader list. */
    fun processingOf(list: ByteArray): ByteArray = list + ":proc".toByteArray(UTF_8)

    /** The count of values a service's input [list] holds, with its processing list (a frame holds many values). */
    fun queuedOf(list: ByteArray): ByteArray = queuedKey(list)

    /** The counter of values a reader list lost to retention (maintained by the scripts). */
    fun missedOf(list: ByteArray): ByteArray = list + ":missed".toByteArray(UTF_8)

    /** The list a synchronous caller receives its replies on. */
    fun reply(id: String): ByteArray = key("reply:$id")

    /** The mark of a call whose caller gave up after a service took its request ([AbandonedCalls]). */
    fun abandonedCall(id: Long): ByteArray = key("call:$id:abandoned")

    /** What every reply list's key starts with; a request naming another key is refused. */
    val replyPrefix: ByteArray = key("reply:")

    /** The fingerprint of the codec the topology's processes use. */
    val codec: ByteArray = key("codec")

    /** A key that is never written: the list [CommandCheck] moves nothing from, to see that Redis knows `LMOVE`. */
    val commandProbe: ByteArray = key("command-probe")

    /** The set of the ids of the topology's core instances (processes) that registered a lease. */
    val instances: ByteArray = key("instances")

    /** The liveness lease of one core instance: a string (who it is) that expires unless renewed. */
    fun instanceLease(instance: String): ByteArray = key("inst:$instance:lease")

    /** What one core instance owns: a hash from each of its reader and reply lists to the reader set it is in (or empty). */
    fun instanceLists(instance: String): ByteArray = key("inst:$instance:lists")

    /**
     * How many declarations (registrations, ownership records) one core instance has made: the
     * instance counts them too, and a smaller number in Redis means Redis lost some of its writes.
     */
    fun instanceDeclared(instance: String): ByteArray = key("inst:$instance:declared")

    /** The host lease of a service: the id of the one instance that runs it; expires unless renewed. */
    fun hostLease(service: String): ByteArray = key("svc:$service:host")

    /** The hosting mode the hosts of a service declared ([Hosting]); expires unless a host renews it. */
    fun hostingMode(service: String): ByteArray = key("svc:$service:hosting")

    /** The instances that host an [Hosting.UNORDERED] service, each with a processing list and lease of its own. */
    fun serviceHosts(service: String): ByteArray = key("svc:$service:hosts")

    /** The lease of one host of an [Hosting.UNORDERED] service: the token of its current run; expires unless renewed. */
    fun hostSeatLease(service: String, instance: String): ByteArray = key("svc:$service:host:$instance")

    /** The processing list of one host of an [Hosting.UNORDERED] service. */
    fun hostProcessing(service: String, instance: String): ByteArray = key("svc:$service:proc:$instance")

    /** A random token written once per life of the topology's data: a new one means Redis lost the data. */
    val epoch: ByteArray = key("epoch")

    private fun key(suffix: String) = (prefix + suffix).toByteArray(UTF_8)
}

/** The count of values a service's input [list] holds, with its processing list (see [Keys.queuedOf]). */
internal fun queuedKey(list: ByteArray): ByteArray = list + ":queued".toByteArray(UTF_8)

package dev.prime.optimus

import redis.clients.jedis.Jedis
import redis.clients.jedis.args.ListDirection
import java.nio.charset.StandardCharsets.UTF_8

/**
 * What one step of a consumer stores in Redis, run as one [Script.STEP]: values for the next
 * service of a chain, replies, dead letters, values published to a source, the acknowledgement of
 * the entries it processed, and the taking of the next entries.
 *
 * A service builds one batch per entry it handled and [combine]s them into one step; if Redis
 * refuses the combined step for a reason other than the connection, it stores the parts one at a
 * time to find the entry at fault (see [StageService]).
 */
internal class StepBatch(
    private val processing: ByteArray,
    private val input: ByteArray,
    private val output: SourceKeys?,
    private val dead: ByteArray?,
    private val deadTrimmed: ByteArray?,
    private val next: ByteArray?,
    private val rules: StepRules,
    /** The host lease this step must hold (a hosted service's step), or `null` (readers, publishers). */
    private val fence: HostFence? = null,
    /** Whether the input's queue count is kept: a service fed by a source (a service only called gets requests, never counted). */
    private val counted: Boolean = false,
) {
    /** A plain consumer's step (a reader): acknowledge and take, nothing stored. */
    constructor(processing: ByteArray, input: ByteArray, output: SourceKeys?) :
        this(processing, input, output, null, null, null, StepRules.PLAIN)

    private val nextValues = ArrayList<ByteArray>()
    private val replies = ArrayList<Reply>()
    private val deadValues = ArrayList<ByteArray>()
    private val published = ArrayList<ByteArray>()

    /** Ids of the values this step handled; remembered once the step is stored. */
    val ids: IdList = IdList()

    private class Reply(val key: ByteArray, val position: Int, val value: ByteArray)

    /** Pushes [value] to the next service of the chain. */
    fun next(value: ByteArray) {
        checkNotNull(next) { "this service is the last of its chain" }
        nextValues += value
    }

    /** Pushes [value] to the reply list [key], checked by the script (see [Script.STEP]). */
    fun reply(key: ByteArray, value: ByteArray) {
        replies += Reply(key, 0, value)
    }

    /** Stores a dead letter (an encoded [DeadLetter]). */
    fun dead(value: ByteArray) {
        checkNotNull(dead) { "this consumer keeps no dead letters" }
        deadValues += value
    }

    /** Publishes [value] to the output source. */
    fun publish(value: ByteArray) {
        checkNotNull(output) { "this service has no output source" }
        published += value
    }

    /** Whether this step publishes to its output source (and so needs a current view of its readers). */
    val publishes: Boolean get() = published.isNotEmpty()

    /** A batch like this one, empty: the part for one more entry. */
    fun part(): StepBatch = StepBatch(processing, input, output, dead, deadTrimmed, next, rules, fence, counted)

    /**
     * Stores the step: acknowledges [ack] entries, takes up to [take] new ones (and at most
     * [StepRules.batchBytes], at least one). [strict]: a service queue this step publishes to must
     * have room for all of its values (a publisher); otherwise it must merely not be full (a
     * service's output, which may overshoot by one batch so it always makes progress).
     */
    fun execute(jedis: Jedis, ack: Int, take: Int, strict: Boolean = false): StepResult {
        val view = if (published.isEmpty()) SourceView.NONE else checkNotNull(output!!.view) { "no view of the readers" }
        // what is ready travels together: a source's values always in frames (numbered there), a hop's when more than one
        // requests travel alone (a queue count counts a frame's elements as values, and a caller's request as nothing)
        val (forwardedValues, requests) = nextValues.partition(Envelope::isValue)
        val nextEntries = Frame.pack(forwardedValues, rules.frameBytes, always = false) + requests
        val publishedFrames = Frame.pack(published, rules.frameBytes, always = true)
        val replyKeys = LinkedHashMap<ByteKey, Int>()
        for (reply in replies) replyKeys.getOrPut(ByteKey(reply.key)) { replyKeys.size + 1 }
        val keys = ArrayList<ByteArray>(13 + replyKeys.size + 2 * view.readers.size + 2 * view.services.size)
        keys += processing
        keys += input
        keys += dead ?: processing
        keys += deadTrimmed ?: processing
        keys += next ?: processing
        keys += output?.log ?: processing
        keys += output?.readers ?: processing
        keys += output?.services ?: processing
        keys += fence?.lease ?: processing
        keys += output?.sequence ?: processing
        keys += if (counted) queuedKey(input) else processing
        keys += next?.let(::queuedKey) ?: processing
        keys += output?.numbers ?: processing
        replyKeys.keys.forEach { keys += it.bytes }
        keys += view.readers
        keys += view.missed
        keys += view.services
        view.services.forEach { keys += queuedKey(it) }
        val args = ArrayList<ByteArray>(22 + view.services.size + nextEntries.size + 3 * replies.size + deadValues.size + publishedFrames.size)
        args += number(ack)
        args += number(take)
        args += number(rules.batchBytes)
        args += number(rules.maxEntryBytes)
        args += number(output?.retention ?: 1)
        args += number(rules.deadLetterLimit)
        args += number(if (next == null) 0 else rules.queueLimit(next))
        args += number(if (strict) 1 else 0)
        args += rules.replyPrefix
        args += number(rules.replyTtlMillis)
        args += number(replyKeys.size)
        args += number(view.readers.size)
        args += number(view.services.size)
        args += number(nextEntries.size)
        args += number(replies.size)
        args += number(deadValues.size)
        args += number(publishedFrames.size)
        args += fence?.instance ?: ByteArray(0)
        args += number(published.size)
        args += number(if (counted) 1 else 0)
        args += number(nextEntries.sumOf(Frame::queued))
        view.services.forEach { args += number(rules.queueLimit(it)) }
        args += nextEntries
        for (reply in replies) {
            args += number(replyKeys.getValue(ByteKey(reply.key)))
            args += number(reply.position)
            args += reply.value
        }
        args += deadValues
        args += publishedFrames
        return StepResult.parse(Script.STEP.run(jedis, keys, args), view)
    }

    /** Stores the step of a plain consumer; returns the entries taken next (already in the processing list). */
    fun run(jedis: Jedis, ack: Int, take: Int): List<ByteArray> {
        val result = execute(jedis, ack, take)
        check(result is StepResult.Stored) { "a plain consumer's step was refused: $result" }
        return result.taken.map { it.bytes }
    }

    companion object {
        /** One step storing every part, in order; the parts' replies are checked against their own entries. */
        fun combine(parts: List<StepBatch>): StepBatch {
            val first = parts.first()
            val whole = first.part()
            parts.forEachIndexed { position, part ->
                whole.nextValues += part.nextValues
                part.replies.forEach { whole.replies += Reply(it.key, position, it.value) }
                whole.deadValues += part.deadValues
                whole.published += part.published
                whole.ids += part.ids
            }
            return whole
        }

        private fun number(n: Number): ByteArray = n.toString().toByteArray(UTF_8)
    }
}

/**
 * A plain reader's step without the script, for a list that carries frames: acknowledges the
 * first [ack] entries of [processing] and moves up to [entries] entries from [list] to it, each
 * with its own `LMOVE` (atomic: an entry is always in one of the two lists), all in one pipelined
 * round trip. Redis then copies a frame once, into the reply, instead of into a Lua string and
 * then into the reply (the script's `LMOVE` costs about twice the plain command for a frame of
 * 256 values of 100 B). Returns the entries moved, in order.
 */
internal fun takeEntries(jedis: Jedis, processing: ByteArray, list: ByteArray, ack: Int, entries: Int): List<ByteArray> {
    val pipeline = jedis.pipelined()
    if (ack > 0) pipeline.ltrim(processing, ack.toLong(), -1)
    val moved = (1..entries).map { pipeline.lmove(list, processing, ListDirection.LEFT, ListDirection.RIGHT) }
    pipeline.sync()
    return moved.mapNotNull { it.get() }
}

/** Limits and namespaces every step of one core follows. */
internal class StepRules(
    /** Reply keys must start with it. */
    val replyPrefix: ByteArray,
    /** The expiry a reply list gets whenever a reply is pushed. */
    val replyTtlMillis: Long,
    /** The most dead letters kept per service. */
    val deadLetterLimit: Int,
    /** An entry above it is taken as its size and a prefix, not read whole. */
    val maxEntryBytes: Int,
    /** A step takes entries until they reach this many bytes (always at least one). */
    val batchBytes: Int,
    /** The queue limit of a service, by its input key. */
    val queueLimit: (ByteArray) -> Int,
    /** The most bytes of a frame (one entry holding many values; a single value may need more). */
    val frameBytes: Int = Frame.DEFAULT_BYTES,
) {
    companion object {
        const val DEFAULT_BATCH_BYTES: Int = 8 * 1024 * 1024

        /** For consumers that only acknowledge and take. */
        val PLAIN: StepRules = StepRules(ByteArray(0), 1, Int.MAX_VALUE, Int.MAX_VALUE, DEFAULT_BATCH_BYTES, { Int.MAX_VALUE })
    }
}

/** An entry a step took: whole, or (above the largest entry size) its first bytes and its size. */
internal class TakenEntry(val bytes: ByteArray, val size: Long) {
    val isWhole: Boolean get() = bytes.size.toLong() == size
}

/** What the step script answered. */
internal sealed class StepResult {
    /** Stored; [missed] per reader of [view] (what retention trimmed from each), [taken] the next entries. */
    class Stored(val taken: List<TakenEntry>, val missed: List<Long>, val view: SourceView) : StepResult()

    /**
     * The service's host lease is not this instance's: [holder] holds it (empty: nobody, e.g. it
     * lapsed while this process was paused, or Redis lost it); nothing was stored.
     */
    class Fenced(val holder: String) : StepResult() {
        override fun toString(): String = "Fenced[${holder.ifEmpty { "nobody" }}]"
    }

    /**
     * The service's processing list holds other than just the entries it handled: another
     * connection moved an entry there (an earlier host's blocking take that Redis ran after the host lease
     * changed hands). Nothing was stored; the service reads the list again (see [StageService]).
     */
    object Stray : StepResult() {
        override fun toString(): String = "Stray"
    }

    /** The caller's view of the source's readers is out of date; nothing was stored. */
    object Stale : StepResult()

    /** The service queue [key] holds [length] of its [limit] entries; nothing was stored. */
    class Full(val key: ByteArray, val length: Long, val limit: Long) : StepResult() {
        override fun toString(): String = "Full[${key.toString(UTF_8)}: $length of $limit]"
    }

    companion object {
        fun parse(reply: Any?, view: SourceView): StepResult {
            val items = reply as List<*>
            return when (val status = (items[0] as ByteArray).toString(UTF_8)) {
                "OK" -> Stored(
                    items.subList(2, items.size).map { item ->
                        if (item is ByteArray) TakenEntry(item, item.size.toLong())
                        else (item as List<*>).let { TakenEntry(it[1] as ByteArray, it[0] as Long) }
                    },
                    (items[1] as List<*>).map { it as Long },
                    view,
                )
                "STALE" -> Stale
                "STRAY" -> Stray
                "FENCED" -> Fenced((items[1] as ByteArray).toString(UTF_8))
                "FULL" -> Full(items[1] as ByteArray, items[2] as Long, items[3] as Long)
                else -> throw IllegalStateException("unexpected answer of the step script: $status")
            }
        }
    }
}

/** The host lease a hosted service's step checks: its key and the id of this core instance. */
/**
 * What a step of a hosted service checks: [lease] holds [instance]. [claimMillis]: for a
 * service's own host lease, its lease time, with which the service re-claims the lease it finds
 * free as it reads its processing list ([Script.PEEK]); `null` for a seat of an unordered
 * service, whose lease only its heartbeat claims.
 */
internal class HostFence(val lease: ByteArray, val instance: ByteArray, val claimMillis: ByteArray? = null)

/** The keys and retention of a source, for publishing to it, and the publisher's view of its readers. */
internal class SourceKeys(
    val name: String,
    val log: ByteArray,
    val readers: ByteArray,
    val services: ByteArray,
    val retention: Int,
    /** The counter numbering the source's values (the step script trims the log and readers by it). */
    val sequence: ByteArray,
) {
    /**
     * A list parallel to the log: for each log entry, the number of its first value and its count
     * (`>I8I4`), so the step script trims the log and the reader lists (each the newest entries of
     * the log) by value numbers without reading a frame.
     */
    val numbers: ByteArray = log + ":numbers".toByteArray(UTF_8)

    /** The reader and service lists this process last saw; the step script says when it is out of date. */
    @Volatile
    var view: SourceView? = null

    /** Reads the source's reader and service sets (one round trip) into [view]. */
    fun refreshView(jedis: Jedis, keys: Keys) {
        val pipeline = jedis.pipelined()
        val plain = pipeline.smembers(readers)
        val queues = pipeline.smembers(services)
        pipeline.sync()
        val readerLists = plain.get().toList()
        view = SourceView(readerLists, readerLists.map(keys::missedOf), queues.get().toList())
    }
}

/** A publisher's view of a source: its plain reader lists (and their missed counters) and its service inputs. */
internal class SourceView(val readers: List<ByteArray>, val missed: List<ByteArray>, val services: List<ByteArray>) {
    companion object {
        val NONE: SourceView = SourceView(emptyList(), emptyList(), emptyList())
    }
}

/** Ids in the order they were added, unboxed (a step handles up to [StageService.BATCH] values, each with its id). */
internal class IdList {
    private var ids = LongArray(2) // most parts hold one id (a lone request or value); a batch grows it
    private var size = 0

    operator fun plusAssign(id: Long) {
        if (size == ids.size) ids = ids.copyOf(size * 2)
        ids[size++] = id
    }

    operator fun plusAssign(other: IdList) {
        for (k in 0 until other.size) this += other.ids[k]
    }

    inline fun forEach(action: (Long) -> Unit) {
        for (k in 0 until size()) action(get(k))
    }

    fun size(): Int = size

    operator fun get(index: Int): Long = ids[index]
}

/** A byte array as a map key (by content). */
internal class ByteKey(val bytes: ByteArray) {
    override fun equals(other: Any?): Boolean = other is ByteKey && bytes.contentEquals(other.bytes)

    override fun hashCode(): Int = bytes.contentHashCode()
}

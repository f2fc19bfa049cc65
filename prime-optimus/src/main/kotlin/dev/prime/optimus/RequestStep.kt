package dev.prime.optimus

import redis.clients.jedis.Jedis
import java.nio.charset.StandardCharsets.UTF_8

/**
 * The one entry a step of a service only called stores for a lone request: the caller's reply
 * ([isReply], pushed to the reply list [target]) or, in a chain, the request forwarded to the next
 * service's input [target].
 */
internal class RequestOutput(val target: ByteArray, val entry: ByteArray, val isReply: Boolean)

/**
 * The step of a service only called (no source feeds it, so its input holds requests and keeps
 * no queue count) that handled one request into one [RequestOutput]: the call's hot path, run as
 * [Script.REQUEST_STEP] instead of the general [Script.STEP]. It keeps every promise of the general
 * step that applies to such a step, in the same order and atomically: the host-lease fence, the
 * reply namespace check and expiry, the acknowledgement of the request, and the take of the next
 * entries under the same bounds; what it cannot store itself (a reply key it refuses) it leaves
 * untouched, and the caller then runs the general step, which dead-letters the request.
 */
internal class RequestStep(
    private val processing: ByteArray,
    private val input: ByteArray,
    private val fence: HostFence,
    private val rules: StepRules,
) {
    private val batchBytes = number(rules.batchBytes)
    private val maxEntryBytes = number(rules.maxEntryBytes)
    private val replyTtl = number(rules.replyTtlMillis)

    /**
     * Stores [output], acknowledges the request (the head of the processing list) and takes up to
     * [take] entries. Returns [StepResult.Stored] or [StepResult.Fenced], or `null` if the script
     * refused the reply key and stored nothing (run the general step for this request).
     */
    fun execute(jedis: Jedis, output: RequestOutput, take: Int): StepResult? {
        val keys = listOf(processing, input, fence.lease, output.target)
        val args = listOf(
            fence.instance,
            output.entry,
            if (output.isReply) ONE else ZERO,
            rules.replyPrefix,
            replyTtl,
            number(take),
            batchBytes,
            maxEntryBytes,
        )
        val items = Script.REQUEST_STEP.run(jedis, keys, args) as List<*>
        return when (val status = (items[0] as ByteArray).toString(UTF_8)) {
            "OK" -> StepResult.Stored(
                if (items.size == 1) emptyList() else items.subList(1, items.size).map(::takenEntry),
                emptyList(),
                SourceView.NONE,
            )
            "FENCED" -> StepResult.Fenced((items[1] as ByteArray).toString(UTF_8))
            "REFUSED" -> null
            else -> throw IllegalStateException("unexpected answer of the request step script: $status")
        }
    }

    private companion object {
        val ONE = "1".toByteArray(UTF_8)
        val ZERO = "0".toByteArray(UTF_8)

        fun number(n: Number): ByteArray = n.toString().toByteArray(UTF_8)

        /** An entry as the script returns it: whole, or `{size, prefix}` above the largest entry size. */
        fun takenEntry(item: Any?): TakenEntry =
            if (item is ByteArray) TakenEntry(item, item.size.toLong())
            else (item as List<*>).let { TakenEntry(it[1] as ByteArray, it[0] as Long) }
    }
}

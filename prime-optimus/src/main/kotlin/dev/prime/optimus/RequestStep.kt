package dev.prime.optimus

import redis.clients.jedis.Jedis
import redis.clients.jedis.Protocol
import redis.clients.jedis.exceptions.JedisNoScriptException
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
 *
 * [executeThenWait] writes the service's next blocking take (`BLMOVE input processing`) behind
 * the step, in the same write, as a raw echo's pop follows its push: a service that is keeping up
 * costs Redis one read per request, not two. The step then leaves one entry of a backlog in the
 * input for that take, so the take never waits while the service holds entries to handle. What the
 * take moved is in the processing list behind what the step took, as a crash would leave it.
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
    fun execute(jedis: Jedis, output: RequestOutput, take: Int): StepResult? =
        parse(Script.REQUEST_STEP.run(jedis, keys(output), args(output, take, waitBehind = false)))

    /**
     * [execute] with a full take, then the blocking take of the next entry (waiting up to
     * [waitSeconds]), in one write; the step's result as [execute]'s, a stored step's taken
     * entries followed by the one the blocking take moved, if it moved one.
     * A step Redis refused throws its error once both answers are read (what the blocking take
     * moved is then in the processing list, for the service to read there); a blocking take Redis
     * refused counts as one that moved nothing.
     */
    fun executeThenWait(jedis: Jedis, output: RequestOutput, take: Int, waitSeconds: ByteArray): StepResult? {
        val connection = jedis.connection
        Script.REQUEST_STEP.send(connection, keys(output), args(output, take, waitBehind = true))
        connection.sendCommand(Protocol.Command.BLMOVE, input, processing, LEFT, RIGHT, waitSeconds)
        val answers = connection.getMany(2)
        val step = answers[0]
        val result = when (step) {
            // Redis lost its scripts (a restart): nothing was stored; the request is still the processing list's head
            is JedisNoScriptException -> execute(jedis, output, take = 0)
            is RuntimeException -> throw step
            else -> parse(step)
        }
        // a blocking take Redis refused moved nothing (never thrown here: the step may be stored); the next take meets it again
        val moved = (answers[1] as? ByteArray)?.let { TakenEntry(it, it.size.toLong()) }
        return if (result is StepResult.Stored && moved != null) StepResult.Stored(result.taken + moved, result.missed, result.view) else result
    }

    private fun keys(output: RequestOutput) = listOf(processing, input, fence.lease, output.target)

    private fun args(output: RequestOutput, take: Int, waitBehind: Boolean) = listOf(
        fence.instance,
        output.entry,
        if (output.isReply) ONE else ZERO,
        rules.replyPrefix,
        replyTtl,
        number(take),
        batchBytes,
        maxEntryBytes,
        if (waitBehind) ONE else ZERO,
    )

    private fun parse(answer: Any?): StepResult? {
        val items = answer as List<*>
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
        val LEFT = "LEFT".toByteArray(UTF_8)
        val RIGHT = "RIGHT".toByteArray(UTF_8)

        fun number(n: Number): ByteArray = n.toString().toByteArray(UTF_8)

        /** An entry as the script returns it: whole, or `{size, prefix}` above the largest entry size. */
        fun takenEntry(item: Any?): TakenEntry =
            if (item is ByteArray) TakenEntry(item, item.size.toLong())
            else (item as List<*>).let { TakenEntry(it[1] as ByteArray, it[0] as Long) }
    }
}

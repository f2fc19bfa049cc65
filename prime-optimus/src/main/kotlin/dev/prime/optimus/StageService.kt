package dev.prime.optimus

import dev.prime.ChainFailedException
import kotlinx.coroutines.currentCoroutineContext
import kotlinx.coroutines.delay
import kotlinx.coroutines.ensureActive
import org.slf4j.LoggerFactory
import redis.clients.jedis.args.ListDirection

/** What a service does with one input: emit any number of outputs (a chain emits exactly one). */
internal fun interface StageLogic {
    fun process(input: Any?, emit: (Any?) -> Unit)
}

/**
 * One Optimus service: a coroutine that moves values from its input list into its processing
 * list, processes them, and in one atomic [Script.STEP] stores the results (the next service's
 * input, a reply, a source, dead letters), acknowledges the inputs and takes the next ones.
 *
 * Design note. Jedis is blocking, so the coroutine runs on the core's own elastic thread pool
 * and blocks there; a blocking take asks Redis for at most one second, and closing the core
 * closes the connection, which wakes it at once. A value is removed from the processing list only
 * in the step that stores its results, so a crash of the process or of Redis (with persistence)
 * loses nothing: on start and after every reconnection the service first processes what its
 * processing list holds. Values seen recently (by id) are acknowledged without processing them
 * again, which absorbs duplicates from a producer that retried a push.
 *
 * Memory: one batch of at most [BATCH] values, and the last 4096 ids.
 */
internal class StageService(
    val name: String,
    private val core: OptimusCore,
    private val logic: StageLogic,
    /** The input list of the next service of the chain, or `null` if this one is the last. */
    private val next: ByteArray?,
    /** Where the last service of a chain linked to a source publishes. */
    private val output: SourceKeys?,
) {
    val input: ByteArray = core.keys.serviceInput(name)
    private val processing = core.keys.serviceProcessing(name)
    private val dead = core.keys.deadLetters(name)
    private val recent = RecentIds()

    suspend fun run() {
        RedisSession(core.connections).use { session -> loop(session) }
    }

    private suspend fun loop(session: RedisSession) {
        var pending: List<ByteArray>? = null // null: read the processing list first
        val backoff = Backoff()
        var outage = false
        while (true) {
            currentCoroutineContext().ensureActive()
            if (core.connections.isClosed) return
            try {
                val taken = pending ?: session.once { it.lrange(processing, 0, -1) }
                if (taken.isEmpty()) {
                    val one = session.once { it.blmove(input, processing, ListDirection.LEFT, ListDirection.RIGHT, RedisConnections.POLL_SECONDS) }
                    pending = if (one == null) emptyList() else listOf(one)
                } else {
                    val step = StepBatch(processing, input, output)
                    for (raw in taken) handle(raw, step)
                    pending = session.once { step.run(it, ack = taken.size, take = BATCH) }
                    step.ids.forEach(recent::add)
                }
                if (outage) LOG.info("service '{}' reconnected to Redis", name)
                outage = false
                backoff.reset()
            } catch (e: Exception) {
                if (core.connections.isClosed) return
                if (!outage) LOG.warn("service '{}' lost Redis ({}); retrying", name, e.toString())
                outage = true
                pending = null
                delay(backoff.next())
            }
        }
    }

    private fun handle(raw: ByteArray, step: StepBatch) {
        val envelope = try {
            Envelope.parse(raw)
        } catch (e: CodecException) {
            step.push(dead, DeadLetter.encode("undecodable envelope: ${e.message}", raw))
            return
        }
        // a duplicate of a value handled recently, or earlier in this batch
        if (envelope.id in recent || !step.ids.add(envelope.id)) return
        val value = try {
            envelope.payload()?.let(core.codec::decode)
        } catch (e: CodecException) {
            step.push(dead, DeadLetter.encode("cannot decode the value: ${e.message}", raw))
            if (envelope.kind == Envelope.Kind.REQUEST) {
                step.push(envelope.replyTo!!, Envelope.replyError(envelope.id, name, e.toString()))
            }
            return
        }
        when (envelope.kind) {
            Envelope.Kind.REQUEST -> handleRequest(envelope, value, step)
            Envelope.Kind.VALUE -> handleValue(envelope, value, raw, step)
            else -> step.push(dead, DeadLetter.encode("a ${envelope.kind} does not belong in a service's input", raw))
        }
    }

    private fun handleRequest(envelope: Envelope, value: Any?, step: StepBatch) {
        val replyTo = envelope.replyTo!!
        try {
            var result: Any? = null
            logic.process(value) { result = it }
            val payload = core.encode(result)
            if (next != null) {
                step.push(next, Envelope.request(envelope.id, replyTo, payload))
            } else {
                step.push(replyTo, Envelope.replyOk(envelope.id, payload))
            }
        } catch (e: VirtualMachineError) {
            throw e
        } catch (e: Throwable) {
            val failure = e as? ChainFailedException ?: ChainFailedException(name, e)
            core.rememberFailure(envelope.id, failure)
            step.push(replyTo, Envelope.replyError(envelope.id, failure.chainName(), failure.cause.toString()))
        }
    }

    private fun handleValue(envelope: Envelope, value: Any?, raw: ByteArray, step: StepBatch) {
        var attempts = 0
        while (true) {
            attempts++
            val payloads = ArrayList<ByteArray>(1)
            try {
                logic.process(value) { output -> if (output != null) payloads += core.encode(output)!! }
            } catch (e: VirtualMachineError) {
                throw e
            } catch (e: Throwable) {
                if (core.connections.isClosed) return
                if (attempts <= core.retries) continue
                core.reportFailure(name, value ?: "null", e)
                step.push(dead, DeadLetter.encode("failed after $attempts attempt(s): $e", raw))
                return
            }
            payloads.forEachIndexed { index, payload ->
                val id = if (payloads.size == 1) envelope.id else ValueIds.derive(envelope.id, index)
                val forwarded = Envelope.value(id, payload)
                when {
                    next != null -> step.push(next, forwarded)
                    output != null -> step.publish(forwarded)
                }
            }
            return
        }
    }

    override fun toString(): String = "service '$name'"

    companion object {
        /** The most values one step takes. */
        const val BATCH = 256
        private val LOG = LoggerFactory.getLogger(StageService::class.java)
    }
}

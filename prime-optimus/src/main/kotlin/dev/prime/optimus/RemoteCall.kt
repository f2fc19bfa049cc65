package dev.prime.optimus

import dev.prime.Block
import dev.prime.ChainFailedException
import dev.prime.PrimeException
import dev.prime.internal.Deadlines.boundedNanos
import java.nio.channels.ClosedByInterruptException

/**
 * The block of an Optimus chain: a remote call. Pushes the input, with a fresh id and the
 * caller's reply list, to the chain's first service and waits for the reply with that id, so
 * each of many concurrent callers gets its own result. A failure reaches the caller as
 * [ChainFailedException] naming the service; in the process that ran the service it is the very
 * exception the block threw.
 */
internal class RemoteCall<I, O>(
    private val core: OptimusCore,
    private val chainName: String,
    private val input: ByteArray,
) : Block<I, O> {
    override fun process(value: I): O {
        core.checkOpen()
        core.checkStarted("calling chain '$chainName'")
        val payload = core.encode(value)
        val slot = core.borrowSlot()
        try {
            @Suppress("UNCHECKED_CAST")
            return core.explainingRefusals("calling chain '$chainName'") { slot.call(input, payload, chainName) } as O
        } finally {
            core.returnSlot(slot)
        }
    }

    override fun toString(): String = "RemoteCall[$chainName]"
}

/**
 * A reply list and the connection to wait on it, used by one call at a time.
 *
 * Design note. A call is retried when its connection breaks, and a retry must never lose the
 * reply: the request may have reached Redis before the break, and the service answers it once
 * (it skips the repeated request as a duplicate). So the reply list is emptied only by the first
 * attempt to send a request, in the same write (`DEL reply; RPUSH request`), when no reply
 * to this call can exist yet; a retry only pushes the request again. The reply is read without
 * removing it (`BLMOVE reply reply`, a rotation), so it is not lost either when the connection
 * breaks while it travels; it stays until the next call's first attempt clears the list. A reply
 * of an earlier call that gave up is recognised by its id and removed (so the wait does not spin
 * on it); a call that gives up also takes its request back if no service took it yet. An
 * interrupt ends the wait at once ([InterruptibleWait] aborts the blocked connection), so a
 * cancelled caller (a coroutine's `withTimeout`) gives up within a round trip, not a poll slice.
 * The first attempt sends the wait with the push (`DEL; RPUSH; BLMOVE` in one write, read as
 * one pipeline: Redis runs the wait after the push, on the same connection), so a call costs
 * the caller one write and Redis one read, where a bare push then pop costs two of each; only a
 * wait that outlasts the poll slice, a late reply of an earlier call, or a retry waits again.
 * With `replicaAcks` the push is confirmed by the replicas first, then the wait is sent.
 *
 * With a call timeout every Redis operation of the call, connecting included, ends by the
 * deadline ([RedisSession.retryingUntil]): the call fails with [RedisUnavailableException] if
 * Redis could not be reached, or with the timeout [PrimeException] if the service did not reply.
 */
internal class CallerSlot(private val core: OptimusCore, private val replyKey: ByteArray) : AutoCloseable {
    private val session = RedisSession(core.connections)

    fun call(input: ByteArray, payload: ByteArray?, chainName: String): Any? {
        val id = core.ids.next()
        val request = Envelope.request(id, replyKey, payload)
        val timeout = core.callTimeout
        val deadline = timeout?.let { System.nanoTime() + boundedNanos(it) }
        val what = "the call to service '$chainName'"
        var pending = try {
            val wait = core.connections.replicaAcks == null // else the push is confirmed before the wait
            InterruptibleWait(session).run { session.pushAndWait(deadline, input, request, replyKey, wait) }
        } catch (_: ClosedByInterruptException) {
            Thread.currentThread().interrupt() // the check in the loop below withdraws the request
            null
        } catch (e: Exception) {
            if (!RedisConnections.isTransient(e)) throw e
            // the request may or may not be in Redis: push it again (a duplicate is skipped), keep any reply
            session.retryingUntil(deadline, what) { it.rpush(input, request) }
            null
        }
        while (true) {
            pending?.let { reply ->
                pending = null
                val envelope = Envelope.parse(reply)
                if (envelope.id == id) return answer(envelope, id)
                session.retryingUntil(deadline, what) { it.lrem(replyKey, 1, reply) } // a late reply to an earlier call
            }
            if (Thread.currentThread().isInterrupted) {
                withdraw(input, request)
                throw PrimeException("interrupted while waiting for the reply of service '$chainName'")
            }
            if (deadline != null && deadline - System.nanoTime() <= 0) {
                withdraw(input, request)
                throw PrimeException(
                    "service '$chainName' did not reply within $timeout; is a process that hosts it " +
                        "running and connected to the same Redis? (OptimusCore.Builder.callTimeout sets the limit)",
                )
            }
            pending = try {
                InterruptibleWait(session).run { session.blockingMoveUntil(deadline, what, replyKey, replyKey) }
            } catch (_: ClosedByInterruptException) {
                Thread.currentThread().interrupt() // the flag is set; say so should a wait have cleared it
                null // the check above withdraws the request and ends the call
            }
        }
    }

    private fun answer(envelope: Envelope, id: Long): Any? = when (envelope.kind) {
        Envelope.Kind.REPLY_OK -> envelope.payload()?.let(core.codec::decode)
        Envelope.Kind.REPLY_ERROR -> throw core.takeFailure(id)
            ?: ChainFailedException(envelope.failedChain!!, RemoteFailureException(envelope.failedChain, envelope.failure!!))
        else -> throw CodecException("unexpected ${envelope.kind} in a reply list")
    }

    /**
     * Takes back the request of a call that gave up, if no service took it yet (every copy a
     * retry pushed), so an abandoned request is neither run nor answered later. One quick
     * attempt: if Redis does not answer at once, the request stays and its late reply is skipped.
     */
    private fun withdraw(input: ByteArray, request: ByteArray) {
        try {
            session.once(System.nanoTime() + WITHDRAW_BOUND_NANOS, 0) { it.lrem(input, 0, request) }
        } catch (_: RuntimeException) {
            // best effort: Redis is unreachable, or the core closed
        }
    }

    override fun close() = session.close()

    private companion object {
        const val WITHDRAW_BOUND_NANOS = 200_000_000L
    }
}

/** What a service in another process threw, as far as its reply tells: the exception's text. */
public class RemoteFailureException internal constructor(service: String, description: String) :
    PrimeException("service '$service' failed in another process: $description") {
    private companion object {
        private const val serialVersionUID: Long = 1L
    }
}

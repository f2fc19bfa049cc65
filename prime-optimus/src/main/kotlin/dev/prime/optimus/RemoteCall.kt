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
    /** The chain's first service, the one the call goes to. */
    val firstService: String,
    /** The chain's own services, [firstService] first: each chain of a linked chain. */
    private val services: Set<String>,
    private val input: ByteArray,
) : Block<I, O> {
    /**
     * Set if [firstService] is a user of an isolated chain of this core ([OptimusCore.bindForCalls]):
     * refuses a call from inside that chain. Read once per call; `null` for every other chain.
     */
    @Volatile
    var selfCalls: SelfCalls? = null

    /** Each of [services] by the name a [CallPaths] path gives it. */
    private val serviceKeys: Map<String, String> = services.associateWith { CallPaths.named(core.keys.serviceInput(it)) }

    override fun process(value: I): O {
        core.checkOpen()
        core.checkStarted("calling chain '$chainName'")
        selfCalls?.check(chainName)
        core.refuseCallThroughItself(chainName, services)
        val path = CallPaths.current()
        if (path != null) core.refuseCallOnItsOwnPath(chainName, serviceKeys, path)
        return core.callOfAnotherCore { call(value, path) }
    }

    /** The call itself, once it was found to be no call from inside itself. */
    private fun call(value: I, path: CallPath?): O {
        val flagLeft = core.clearFlagLeftByABlock()
        try {
            if (flagLeft) core.checkOpen() // the flag was the close's: the call fails as a closed core's
            val payload = core.encode(value)
            // the deadline counts from here: a thread's first call records its reply list within it too
            val deadline = core.callTimeout?.let { System.nanoTime() + boundedNanos(it) }
            val slot = core.reachingRedisFor(chainName, sent = false) { core.borrowSlot(deadline, chainName) }
            try {
                @Suppress("UNCHECKED_CAST")
                return core.explainingRefusals("calling chain '$chainName'") { slot.call(input, payload, chainName, deadline, path) } as O
            } finally {
                core.returnSlot(slot)
            }
        } finally {
            if (flagLeft) Thread.currentThread().interrupt()
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
 * With a call timeout every Redis operation of the call, recording a new slot's reply list and
 * connecting included, ends by the deadline ([RedisSession.retryingUntil]): the call fails with
 * [RedisUnavailableException] if Redis could not be reached, or with the timeout [PrimeException]
 * if the service did not reply. Over a slow link (as the reader's timed take does): each reply of
 * Redis gets at least [RedisConnections.LEAST_ANSWER_MS] after Redis's own wait, so a reply a slow link brings late is
 * received, not taken for a dead connection (and the connection stays open); the slot measures
 * its round trip from each wait Redis ended empty and asks Redis to end the next wait that long
 * before the deadline, so the reply comes by it; a wait whose reply could not come back by the
 * deadline is not sent: the request is taken back then, and the call waits out its timeout. A
 * call whose reply comes fast costs no more than before: no round trip, no allocation.
 */
internal class CallerSlot(private val core: OptimusCore, private val replyKey: ByteArray) : AutoCloseable {
    private val session = RedisSession(core.connections)

    /**
     * The last round trip this slot measured to Redis (nanoseconds; 0: none yet), from a wait that
     * Redis ended without a reply: a wait asks Redis to end that much before the call's deadline.
     */
    private var roundTrip = 0L

    /**
     * Calls the service of [chainName] with [payload]; gives up at [deadline] (a [System.nanoTime];
     * `null`: never). [path]: the services that wait for the calling thread ([CallPaths.current]),
     * recorded for the request while the call waits.
     */
    fun call(input: ByteArray, payload: ByteArray?, chainName: String, deadline: Long?, path: CallPath?): Any? {
        val id = core.ids.next()
        val reply = CallPaths.waitingFor(id, path) {
            core.reachingRedisFor(chainName, sent = true) { awaitReply(id, input, payload, chainName, deadline) }
        }
        return answer(reply, id)
    }

    /** Sends the request [id] and returns its reply (see [call]). */
    private fun awaitReply(id: Long, input: ByteArray, payload: ByteArray?, chainName: String, deadline: Long?): Envelope {
        val request = Envelope.request(id, replyKey, payload)
        val what = "the call to service '$chainName'"
        var pending = try {
            val wait = core.connections.replicaAcks == null // else the push is confirmed before the wait
            if (deadline == null) {
                InterruptibleWait(session).run { session.pushAndWait(null, input, request, replyKey, wait) }
            } else {
                // Redis ends the wait a round trip before the deadline, so its reply comes by it; each reply gets a second
                val sent = System.nanoTime()
                val reply = InterruptibleWait(session).run {
                    session.pushAndWait(deadline, input, request, replyKey, wait, roundTrip, RedisConnections.LEAST_ANSWER_MS)
                }
                if (reply == null && wait) measured(sent, deadline - roundTrip)
                reply
            }
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
                if (envelope.id == id) return envelope
                session.retryingUntil(deadline, what) { it.lrem(replyKey, 1, reply) } // a late reply to an earlier call
            }
            if (Thread.currentThread().isInterrupted) {
                withdraw(input, request, id, null)
                throw PrimeException("interrupted while waiting for the reply of service '$chainName'")
            }
            if (deadline != null && deadline - System.nanoTime() <= 0) {
                withdraw(input, request, id, null)
                throw noReply(chainName)
            }
            // no round trip starts that could not come back by the deadline: Redis's wait ends a round trip before it
            val serverDeadline = deadline?.let { it - roundTrip }
            if (deadline != null && serverDeadline!! - System.nanoTime() <= 0) {
                // a reply pushed from now on could not reach this caller by the deadline: take the request
                // back now (its answer comes about at the deadline), then wait out the timeout
                withdraw(input, request, id, deadline)
                try {
                    core.connections.pauseInterruptibly(ceilMillis(deadline - System.nanoTime()))
                } catch (_: InterruptedException) {
                    Thread.currentThread().interrupt()
                    throw PrimeException("interrupted while waiting for the reply of service '$chainName'")
                }
                core.connections.ensureOpen()
                throw noReply(chainName)
            }
            pending = try {
                val sent = System.nanoTime()
                val least = if (serverDeadline == null) 0 else session.waitMillis(serverDeadline) + RedisConnections.LEAST_ANSWER_MS
                InterruptibleWait(session).run {
                    session.blockingMoveUntil(deadline, what, replyKey, replyKey, serverDeadline, least)
                }.also { if (it == null && serverDeadline != null) measured(sent, serverDeadline) }
            } catch (_: ClosedByInterruptException) {
                Thread.currentThread().interrupt() // the flag is set; say so should a wait have cleared it
                null // the check above withdraws the request and ends the call
            } catch (_: LateReply) {
                null // no reply by the deadline (a loaded machine, or a link that froze): the check above ends the call
            }
        }
    }

    /**
     * A wait sent at [sent], asked to end by [serverDeadline], came back empty: the rest of the
     * time it took, past Redis's wait, was the round trip.
     */
    private fun measured(sent: Long, serverDeadline: Long) {
        val waitMillis = session.waitMillis(serverDeadline, sent)
        roundTrip = (System.nanoTime() - sent - waitMillis * 1_000_000).coerceAtLeast(0)
    }

    private fun noReply(chainName: String) = PrimeException(
        "service '$chainName' did not reply within ${core.callTimeout}; is a process that hosts it " +
            "running and connected to the same Redis? (OptimusCore.Builder.callTimeout sets the limit)",
    )

    private fun answer(envelope: Envelope, id: Long): Any? = when (envelope.kind) {
        Envelope.Kind.REPLY_OK -> envelope.value(core)
        Envelope.Kind.REPLY_ERROR -> throw core.takeFailure(id)
            ?: ChainFailedException(envelope.failedChain!!, RemoteFailureException(envelope.failedChain, envelope.failure!!))
        else -> throw CodecException("unexpected ${envelope.kind} in a reply list")
    }

    /**
     * Takes back the request of a call that gave up, if no service took it yet (every copy a
     * retry pushed), so an abandoned request is neither run nor answered later; if a service took
     * it, marks it abandoned, so a block that waits for an isolated chain with it does not run it
     * ([AbandonedCalls]). One attempt: if Redis does not answer by [deadline] (with at least
     * [RedisConnections.LEAST_ANSWER_MS] for its reply), or, past the deadline (`null`), at once,
     * the request stays and its late reply is skipped.
     */
    private fun withdraw(input: ByteArray, request: ByteArray, id: Long, deadline: Long?) {
        val keys = listOf(input, core.keys.abandonedCall(id))
        val args = listOf(request, AbandonedCalls.MARK_MILLIS.toString().toByteArray(Charsets.UTF_8))
        try {
            if (deadline == null) {
                session.once(System.nanoTime() + WITHDRAW_BOUND_NANOS, 0) { AbandonedCalls.WITHDRAW.runText(it, keys, args) }
            } else {
                session.once(deadline, 0, RedisConnections.LEAST_ANSWER_MS) { AbandonedCalls.WITHDRAW.runText(it, keys, args) }
            }
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

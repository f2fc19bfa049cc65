package dev.prime.optimus

import dev.prime.Block
import dev.prime.ChainFailedException
import dev.prime.PrimeException
import redis.clients.jedis.args.ListDirection

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
        val payload = core.encode(value)
        val slot = core.borrowSlot()
        try {
            @Suppress("UNCHECKED_CAST")
            return slot.call(input, payload, chainName) as O
        } finally {
            core.returnSlot(slot)
        }
    }

    override fun toString(): String = "RemoteCall[$chainName]"
}

/**
 * A reply list and the connection to wait on it, used by one call at a time.
 *
 * Design note. The reply is read without removing it (`BLMOVE reply reply`, a rotation), and the
 * list is emptied when the next call is sent, in the same round trip as the request; so a reply
 * is not lost when the connection breaks while it travels, and calls cost two round trips like a
 * bare push and pop. Replies of earlier calls that gave up are recognised by id and skipped.
 */
internal class CallerSlot(private val core: OptimusCore, private val replyKey: ByteArray) : AutoCloseable {
    private val session = RedisSession(core.connections)

    fun call(input: ByteArray, payload: ByteArray?, chainName: String): Any? {
        val id = core.ids.next()
        val request = Envelope.request(id, replyKey, payload)
        session.retrying { jedis ->
            val pipeline = jedis.pipelined()
            pipeline.del(replyKey)
            pipeline.rpush(input, request)
            pipeline.sync()
        }
        val deadline = core.callTimeout?.let { System.nanoTime() + it.toNanos() }
        while (true) {
            if (Thread.currentThread().isInterrupted) {
                throw PrimeException("interrupted while waiting for the reply of service '$chainName'")
            }
            val reply = session.retrying {
                it.blmove(replyKey, replyKey, ListDirection.LEFT, ListDirection.RIGHT, RedisConnections.POLL_SECONDS)
            }
            if (reply == null) {
                if (deadline != null && System.nanoTime() > deadline) {
                    throw PrimeException(
                        "service '$chainName' did not reply within ${core.callTimeout}; is a process that hosts it " +
                            "running and connected to the same Redis? (OptimusCore.Builder.callTimeout sets the limit)",
                    )
                }
                continue
            }
            val envelope = Envelope.parse(reply)
            if (envelope.id != id) continue
            return when (envelope.kind) {
                Envelope.Kind.REPLY_OK -> envelope.payload()?.let(core.codec::decode)
                Envelope.Kind.REPLY_ERROR -> throw core.takeFailure(id)
                    ?: ChainFailedException(envelope.failedChain!!, RemoteFailureException(envelope.failedChain, envelope.failure!!))
                else -> throw CodecException("unexpected ${envelope.kind} in a reply list")
            }
        }
    }

    override fun close() = session.close()
}

/** What a service in another process threw, as far as its reply tells: the exception's text. */
public class RemoteFailureException internal constructor(service: String, description: String) :
    PrimeException("service '$service' failed in another process: $description") {
    private companion object {
        private const val serialVersionUID: Long = 1L
    }
}

package dev.prime.optimus

import java.nio.BufferUnderflowException
import java.nio.ByteBuffer
import java.nio.charset.StandardCharsets.UTF_8

/**
 * What travels in the Redis lists: a value with its id and, for a synchronous call, the list to
 * reply to. Layout: magic byte, kind, 8-byte id, then per kind: the reply key (2-byte length and
 * bytes), the failure (chain name and message), and last the payload (1 byte "present", then the
 * codec's bytes).
 *
 * Every value has an id so that a value pushed twice (a retry after a lost reply) is recognised
 * and processed once; a service keeps the id of its input on what it outputs.
 */
internal class Envelope private constructor(
    val kind: Kind,
    val id: Long,
    val replyTo: ByteArray?,
    private val bytes: ByteArray,
    private val payloadAt: Int,
    private val end: Int,
    val failedChain: String?,
    val failure: String?,
) {
    enum class Kind { VALUE, REQUEST, REPLY_OK, REPLY_ERROR }

    /** The codec bytes of the value, or `null` for a `null` value. */
    fun payload(): ByteArray? =
        if (payloadAt >= end || bytes[payloadAt] == ABSENT) null
        else bytes.copyOfRange(payloadAt + 1, end)

    /**
     * The value, decoded by [core]'s codec where it lies in the envelope's bytes (a [KryoCodec]
     * reads it in place; another codec gets a copy of the [payload]), or `null` for a `null` value.
     *
     * [held]: the caller's session of the codec, if it keeps one across values.
     *
     * @throws CodecException if the codec cannot decode it
     */
    fun value(core: OptimusCore, held: HeldCodecSession? = null): Any? = when {
        payloadAt >= end || bytes[payloadAt] == ABSENT -> null
        else -> core.decode(bytes, payloadAt + 1, end - payloadAt - 1, held)
    }

    companion object {
        private const val MAGIC: Byte = 0x50 // 'P'
        private const val ABSENT: Byte = 0
        private const val PRESENT: Byte = 1
        private const val HEADER = 10

        /** Whether [bytes] is a value's envelope (not a request or a reply): what a service's queue count counts. */
        fun isValue(bytes: ByteArray): Boolean = bytes.size >= HEADER && bytes[0] == MAGIC && bytes[1] == Kind.VALUE.ordinal.toByte()

        fun value(id: Long, payload: ByteArray?): ByteArray = build(Kind.VALUE, id, payload) { }

        /** The bytes a [valueAround] envelope leaves before its payload: the header and the "present" byte. */
        const val VALUE_ROOM: Int = HEADER + 1

        /**
         * A value's envelope made in [encoded] itself, whose first [VALUE_ROOM] bytes were left for
         * it and whose rest is the payload (a codec wrote it there): the same bytes as [value] of
         * that payload, without copying it. The id is 0 until [withId] writes it.
         */
        fun valueAround(encoded: ByteArray): ByteArray {
            ByteBuffer.wrap(encoded).put(MAGIC).put(Kind.VALUE.ordinal.toByte()).putLong(0L).put(PRESENT)
            return encoded
        }

        /** Writes [id] into the value envelope [envelope] (made by [valueAround] or [value]); returns it. */
        fun withId(envelope: ByteArray, id: Long): ByteArray {
            ByteBuffer.wrap(envelope).putLong(2, id)
            return envelope
        }

        fun request(id: Long, replyTo: ByteArray, payload: ByteArray?): ByteArray =
            build(Kind.REQUEST, id, payload, 2 + replyTo.size) { putBytes16(it, replyTo) }

        fun replyOk(id: Long, payload: ByteArray?): ByteArray = build(Kind.REPLY_OK, id, payload) { }

        fun replyError(id: Long, chain: String, message: String): ByteArray {
            val c = chain.toByteArray(UTF_8).let { if (it.size > 0xFFFF) it.copyOf(0xFFFF) else it }
            val m = message.toByteArray(UTF_8)
            return build(Kind.REPLY_ERROR, id, null, 2 + c.size + 4 + m.size) {
                putBytes16(it, c)
                it.putInt(m.size).put(m)
            }
        }

        /** Same value, new kind or id: what a service forwards. */
        fun forward(envelope: Envelope, nextKind: Kind, id: Long, payload: ByteArray?): ByteArray = when (nextKind) {
            Kind.REQUEST -> request(id, envelope.replyTo!!, payload)
            Kind.VALUE -> value(id, payload)
            Kind.REPLY_OK -> replyOk(id, payload)
            Kind.REPLY_ERROR -> throw IllegalArgumentException("an error reply carries no payload")
        }

        /** Reads an envelope; bytes that are not one give a [CodecException]. */
        fun parse(bytes: ByteArray): Envelope = parse(bytes, 0, bytes.size)

        /**
         * Reads the envelope in the [length] bytes of [bytes] from [offset] (one of a frame's), where
         * it lies: the envelope keeps [bytes] and reads its payload there.
         */
        fun parse(bytes: ByteArray, offset: Int, length: Int): Envelope {
            try {
                val buffer = ByteBuffer.wrap(bytes, offset, length)
                if (length < HEADER || buffer.get() != MAGIC) {
                    throw CodecException("not a Prime envelope ($length bytes, wrong header)")
                }
                val kindIndex = buffer.get().toInt()
                val kind = Kind.entries.getOrNull(kindIndex)
                    ?: throw CodecException("unknown envelope kind $kindIndex")
                val id = buffer.long
                var replyTo: ByteArray? = null
                var chain: String? = null
                var message: String? = null
                when (kind) {
                    Kind.REQUEST -> replyTo = bytes16(buffer)
                    Kind.REPLY_ERROR -> {
                        chain = String(bytes16(buffer), UTF_8)
                        val length = buffer.int
                        if (length < 0 || length > buffer.remaining()) throw CodecException("bad failure length $length")
                        message = String(ByteArray(length).also { buffer.get(it) }, UTF_8)
                    }
                    else -> {}
                }
                return Envelope(kind, id, replyTo, bytes, buffer.position(), offset + length, chain, message)
            } catch (e: BufferUnderflowException) {
                throw CodecException("truncated envelope ($length bytes)", e)
            }
        }

        private inline fun build(
            kind: Kind,
            id: Long,
            payload: ByteArray?,
            extra: Int = 0,
            fill: (ByteBuffer) -> Unit,
        ): ByteArray {
            val buffer = ByteBuffer.allocate(HEADER + extra + 1 + (payload?.size ?: 0))
            buffer.put(MAGIC).put(kind.ordinal.toByte()).putLong(id)
            fill(buffer)
            if (payload == null) buffer.put(ABSENT) else buffer.put(PRESENT).put(payload)
            return buffer.array()
        }

        private fun putBytes16(buffer: ByteBuffer, bytes: ByteArray) {
            require(bytes.size <= 0xFFFF) { "key of ${bytes.size} bytes is too long" }
            buffer.putShort(bytes.size.toShort()).put(bytes)
        }

        private fun bytes16(buffer: ByteBuffer): ByteArray {
            val length = buffer.short.toInt() and 0xFFFF
            if (length > buffer.remaining()) throw CodecException("bad key length $length")
            return ByteArray(length).also { buffer.get(it) }
        }
    }
}

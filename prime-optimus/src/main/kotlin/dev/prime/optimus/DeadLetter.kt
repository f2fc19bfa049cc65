package dev.prime.optimus

import java.nio.ByteBuffer
import java.nio.charset.StandardCharsets.UTF_8

/**
 * A value a service could not process: bytes that do not decode, or an input its block failed on
 * (after the configured retries). The service stored it in its dead-letter list, with the
 * reason, and went on with the next value. Read them with [OptimusCore.deadLetters].
 *
 * @property service the service that gave up on the value
 * @property reason why, in words
 */
public class DeadLetter internal constructor(
    public val service: String,
    public val reason: String,
    private val bytes: ByteArray,
) {
    /** The raw bytes as they were in the service's input list (a copy). */
    public fun bytes(): ByteArray = bytes.copyOf()

    override fun toString(): String = "DeadLetter[$service: $reason (${bytes.size} bytes)]"

    internal companion object {
        fun encode(reason: String, raw: ByteArray): ByteArray {
            val text = reason.toByteArray(UTF_8)
            return ByteBuffer.allocate(4 + text.size + raw.size).putInt(text.size).put(text).put(raw).array()
        }

        fun decode(service: String, entry: ByteArray): DeadLetter {
            val buffer = ByteBuffer.wrap(entry)
            val length = if (entry.size >= 4) buffer.int else -1
            if (length < 0 || length > buffer.remaining()) return DeadLetter(service, "(unreadable dead-letter entry)", entry)
            val reason = String(entry, 4, length, UTF_8)
            return DeadLetter(service, reason, entry.copyOfRange(4 + length, entry.size))
        }
    }
}

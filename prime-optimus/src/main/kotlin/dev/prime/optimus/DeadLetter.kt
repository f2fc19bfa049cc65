package dev.prime.optimus

import java.nio.ByteBuffer
import java.nio.charset.StandardCharsets.UTF_8

/**
 * A value a service could not process: bytes that do not decode, an entry above the size limit
 * (only its first KiB is kept), a request whose reply key is not one of the topology's reply
 * lists, an entry whose results Redis refused to store, or an input its block failed on (after
 * the configured retries). A service keeps at most [OptimusCore.Builder.deadLetterLimit] of them;
 * older ones are dropped and counted ([OptimusCore.trimmedDeadLetters]). The service stored it in its dead-letter list, with the
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
        /** The most bytes of an entry a dead letter keeps when the entry was too large to read whole. */
        const val PREFIX_KEPT = 1024

        /** A dead letter of [entry]: the whole entry, or its first bytes when it was too large to read. */
        fun encode(reason: String, entry: TakenEntry): ByteArray =
            if (entry.isWhole) encode(reason, entry.bytes) else encodePrefix(reason, entry)

        /** A dead letter keeping only the first [PREFIX_KEPT] bytes of [entry] (an entry too large to keep). */
        fun encodePrefix(reason: String, entry: TakenEntry): ByteArray {
            val prefix = entry.bytes.copyOf(minOf(entry.bytes.size, PREFIX_KEPT))
            return encode("$reason (only its first ${prefix.size} of ${entry.size} bytes are kept)", prefix)
        }

        /** An entry in words, for a log line: its size and first bytes. */
        fun describe(entry: TakenEntry): String =
            "${entry.size} bytes, starting ${entry.bytes.copyOf(minOf(entry.bytes.size, 32)).joinToString("") { "%02x".format(it) }}"

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

package dev.prime.optimus

import redis.clients.jedis.Jedis
import java.nio.charset.StandardCharsets.UTF_8

/**
 * What one step of a consumer stores in Redis, run as one [Script.STEP]: list pushes (next
 * service, replies, dead letters), values published to a source, the acknowledgement of the
 * entries it processed, and the taking of the next entries.
 */
internal class StepBatch(
    private val processing: ByteArray,
    private val input: ByteArray,
    private val output: SourceKeys?,
) {
    private val pushes = ArrayList<ByteArray>()
    private val published = ArrayList<ByteArray>()

    /** Ids of the values this step handled; remembered once the step is stored. */
    val ids: MutableSet<Long> = LinkedHashSet()

    fun push(list: ByteArray, value: ByteArray) {
        pushes += list
        pushes += value
    }

    fun publish(value: ByteArray) {
        checkNotNull(output) { "this service has no output source" }
        published += value
    }

    /** Stores the step; returns the entries taken next (already in the processing list). */
    @Suppress("UNCHECKED_CAST")
    fun run(jedis: Jedis, ack: Int, take: Int): List<ByteArray> {
        val keys = listOf(processing, input, output?.log ?: processing, output?.readers ?: processing)
        val args = ArrayList<ByteArray>(4 + pushes.size + published.size)
        args += ack.toString().toByteArray(UTF_8)
        args += take.toString().toByteArray(UTF_8)
        args += (output?.retention ?: 1).toString().toByteArray(UTF_8)
        args += (pushes.size / 2).toString().toByteArray(UTF_8)
        args += pushes
        args += published
        return Script.STEP.run(jedis, keys, args) as List<ByteArray>
    }
}

/** The keys and retention of a source, for publishing to it. */
internal class SourceKeys(val log: ByteArray, val readers: ByteArray, val retention: Int)

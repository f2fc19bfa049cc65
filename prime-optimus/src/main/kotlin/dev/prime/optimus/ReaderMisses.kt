package dev.prime.optimus

import org.slf4j.LoggerFactory
import java.nio.charset.StandardCharsets.UTF_8
import java.util.concurrent.ConcurrentHashMap
import java.util.concurrent.atomic.LongAdder

/**
 * Tells, at WARN, what plain readers miss: each publish learns from the step script how many
 * values retention trimmed from each reader list; this adds them up per reader and logs at most
 * one line per reader per [intervalNanos] with the count since its last line. (The total is also
 * kept in Redis and read by `Reader.missed()`; the sum per source, for [dev.prime.Metrics], is
 * [total].) Memory: one small record per reader that missed something, at most [MAX_READERS]
 * (then they start over), and one counter per source.
 */
internal class ReaderMisses(
    private val coreName: String,
    private val intervalNanos: Long = 10_000_000_000L,
    private val clock: () -> Long = System::nanoTime,
    private val warn: (String) -> Unit = LOG::warn,
) {
    private class Tally(val source: SourceKeys, var pending: Long, var lastLine: Long)

    private val tallies = ConcurrentHashMap<ByteKey, Tally>()
    private val totals = ConcurrentHashMap<String, LongAdder>() // per source, for metrics

    fun record(source: SourceKeys, view: SourceView, missed: List<Long>) {
        for (index in missed.indices) {
            val count = missed[index]
            if (count > 0) {
                totals.computeIfAbsent(source.name) { LongAdder() }.add(count)
                record(source, view.readers[index], count)
            }
        }
    }

    /** What the readers of [source] missed in all, as this process's publishes counted it. */
    fun total(source: String): Long = totals[source]?.sum() ?: 0L

    private fun record(source: SourceKeys, reader: ByteArray, count: Long) {
        if (tallies.size > MAX_READERS) tallies.clear()
        val now = clock()
        val tally = tallies.computeIfAbsent(ByteKey(reader)) { Tally(source, 0, now - intervalNanos) }
        val line = synchronized(tally) {
            tally.pending += count
            if (now - tally.lastLine < intervalNanos) return
            tally.lastLine = now
            val lost = tally.pending
            tally.pending = 0
            lost
        }
        warnMissed(source, reader, line)
    }

    /** Writes a line for every reader whose misses were counted but not yet written (at close). */
    fun flush() {
        for ((reader, tally) in tallies) {
            val line = synchronized(tally) {
                val lost = tally.pending
                tally.pending = 0
                lost
            }
            if (line > 0) warnMissed(tally.source, reader.bytes, line)
        }
    }

    private fun warnMissed(source: SourceKeys, reader: ByteArray, count: Long) {
        warn(
            "core '$coreName': reader ${reader.toString(UTF_8)} of source '${source.name}' missed $count value(s) " +
                "(the source retains ${source.retention}; Reader.missed() gives the total): read faster or raise " +
                "CoreConfig.sourceRetention",
        )
    }

    private companion object {
        const val MAX_READERS = 4096
        val LOG = LoggerFactory.getLogger(ReaderMisses::class.java)
    }
}

package dev.prime.optimus

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/** What plain readers miss is logged at most once per reader per interval, with the count since the last line. */
class ReaderMissesTest {

    @Test
    fun missesAreLoggedWithCountsAtMostOncePerReaderPerInterval() {
        var now = 0L
        val lines = ArrayList<String>()
        val misses = ReaderMisses("robot", intervalNanos = 10_000, clock = { now }, warn = { lines += it })
        val source = SourceKeys("imu", "log".toByteArray(), "r".toByteArray(), "s".toByteArray(), 16, "seq".toByteArray())
        val view = SourceView(listOf("a".toByteArray(), "b".toByteArray()), listOf("a:m".toByteArray(), "b:m".toByteArray()), emptyList())

        misses.record(source, view, listOf(3, 0))
        assertEquals(1, lines.size)
        assertTrue("reader a of source 'imu' missed 3 value(s)" in lines[0], lines[0])
        now = 5_000
        misses.record(source, view, listOf(5, 2))
        assertEquals(2, lines.size, "reader a is quiet within the interval; b's first miss is told")
        assertTrue("reader b of source 'imu' missed 2 value(s)" in lines[1], lines[1])
        now = 10_000
        misses.record(source, view, listOf(1, 0))
        assertEquals(3, lines.size)
        assertTrue("reader a of source 'imu' missed 6 value(s)" in lines[2], lines[2])
    }
}

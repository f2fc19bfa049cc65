package dev.prime.optimus

import java.nio.channels.ClosedByInterruptException
import java.nio.channels.spi.AbstractInterruptibleChannel

/**
 * One blocking Redis wait of a [RedisSession] that an interrupt of the waiting thread ends at
 * once: the interrupt aborts the session's connection, the blocked read fails, and [run] throws
 * [ClosedByInterruptException]. Single use, like a channel.
 *
 * Design note. A platform thread blocked in a socket read does not notice `Thread.interrupt()`:
 * without this, a caller sees its interrupt only when its blocking command's server wait ends
 * (up to [RedisConnections.POLL_SECONDS]). The JDK's public way to run code on the interrupting
 * thread is the interruptible-channel protocol: between [begin] and [end] an interrupt calls
 * [implCloseChannel], which here aborts the connection (from the interrupting thread, which
 * [RedisSession.abort] allows). An interrupt that came before [begin] closes it at once, and
 * [run] then does not start the wait. The aborted connection is replaced on the session's next
 * operation.
 */
internal class InterruptibleWait(private val session: RedisSession) : AbstractInterruptibleChannel() {

    /** Runs [wait]; an interrupt meanwhile (or before) ends it with [ClosedByInterruptException]. */
    fun <T> run(wait: () -> T): T {
        var completed = false
        begin()
        try {
            if (!isOpen) throw ClosedByInterruptException()
            return wait().also { completed = true }
        } finally {
            end(completed) // throws ClosedByInterruptException if an interrupt closed this wait
        }
    }

    override fun implCloseChannel() {
        session.abort()
    }
}

package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.Source
import org.junit.jupiter.api.Assertions.assertEquals
import redis.clients.jedis.Jedis
import java.net.URI
import java.time.Duration
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * A publisher on its own embedded Redis and a reader's process behind a [FaultProxy], both with a
 * 1 s lease, for tests that cut the reader's process off until the publisher reclaims its reader.
 * [readerCore] is closed with the rig unless the test closed it first.
 */
internal class CutOffReaderRig(val config: CoreConfig) : AutoCloseable {
    val keys = Keys(config.name())
    private val redis = EmbeddedRedis.start()
    val proxy = FaultProxy(redis.uri)
    val raw = Jedis(URI(redis.uri))
    val publisher: OptimusCore = core(redis.uri)
    val numbers: Source<Int> = publisher.source("numbers", EventBlock<Int>())
    val readerCore: OptimusCore = core(proxy.url)

    /** The source's reader set. */
    val readers: ByteArray get() = keys.sourceReaders("numbers")

    init {
        publisher.start()
    }

    /** Cuts the reader's process off and waits (bounded) until the publisher reclaimed its reader. */
    fun cutOffUntilReclaimed() {
        proxy.refuse()
        awaitReaders(0, "the publisher reclaimed the cut-off reader")
    }

    /** Waits (bounded) until the source's reader set holds [count] readers; fails with [what] if not. */
    fun awaitReaders(count: Long, what: String) {
        val pace = CountDownLatch(1) // never counted down: a bounded pause between looks
        var looks = 0
        while (raw.scard(readers) != count && looks++ < 1000) pace.await(10, TimeUnit.MILLISECONDS)
        assertEquals(count, raw.scard(readers), what)
    }

    private fun core(url: String): OptimusCore =
        OptimusCore.builder().config(config).redis(url).leaseTime(Duration.ofSeconds(1)).hosts(emptyList()).build()

    override fun close() {
        readerCore.close()
        publisher.close()
        raw.close()
        proxy.close()
        redis.close()
    }
}

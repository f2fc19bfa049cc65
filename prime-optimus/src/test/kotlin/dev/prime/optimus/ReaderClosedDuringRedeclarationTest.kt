package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.io.PrintStream
import java.time.Duration
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * A reader closed while its process declares it again after its lease lapsed: `close()`
 * unregisters the reader, and the re-declaration must not register it again (its list would be
 * filled by every publish, and outlive the core's close).
 */
class ReaderClosedDuringRedeclarationTest {

    /**
     * The race made certain: the heartbeat's re-declaration takes its snapshot of the readers, then
     * logs the lapse WARN (the test binding, slf4j-simple, writes it to System.err at the call) and
     * only then registers them. The test holds the heartbeat thread in that WARN's println (bounded),
     * closes the reader, and lets it go on.
     */
    @Test
    fun aReaderClosedWhileItsProcessDeclaresItAgainIsNotRegisteredAgain() {
        val config = CoreConfig.builder().name("close-race-${System.nanoTime()}").sourceRetention(16).build()
        val inRedeclare = CountDownLatch(1)
        val closed = CountDownLatch(1)
        val original = System.err
        val hook = object : PrintStream(original, true) {
            override fun println(x: String?) {
                if (x != null && "lapsed: this process was frozen" in x && config.name() in x && inRedeclare.count > 0L) {
                    inRedeclare.countDown()
                    closed.await(10, TimeUnit.SECONDS) // bounded: the heartbeat goes on after the reader closed
                }
                super.println(x)
            }
        }
        System.setErr(hook)
        try {
            run(config) { reader, proxy ->
                proxy.restore()
                assertTrue(inRedeclare.await(20, TimeUnit.SECONDS), "the reader's process did not start declaring again")
                reader.close() // after the re-declaration's snapshot, before its registrations
                closed.countDown()
            }
        } finally {
            System.setErr(original)
        }
    }

    /** The reader closed while its process is still cut off (after it was reclaimed), then Redis is back. */
    @Test
    fun aReaderClosedWhileItsProcessIsCutOffIsNotRegisteredAgain() {
        val config = CoreConfig.builder().name("close-cut-${System.nanoTime()}").sourceRetention(16).build()
        run(config) { reader, proxy ->
            reader.close() // Redis unreachable: its cleanup gives up after about 2 s, with a WARN
            proxy.restore()
        }
    }

    /**
     * A reader core behind a proxy, cut off until the publisher reclaims its reader, then
     * [closeAndRestore]; then checks that the closed reader is neither in the source's reader set
     * nor a list in Redis after a few more publishes, while its core runs and after it closed.
     */
    private fun run(config: CoreConfig, closeAndRestore: (OptimusReader<*>, FaultProxy) -> Unit) {
        CutOffReaderRig(config).use { rig ->
            val reader = rig.readerCore.source("numbers", EventBlock<Int>()).reader() as OptimusReader<*>
            val list = reader.list
            rig.readerCore.start()
            rig.publisher.publishAll(rig.numbers, listOf(1, 2, 3))
            assertEquals(1, reader.take(Duration.ofSeconds(10)).orElseThrow())

            rig.cutOffUntilReclaimed()
            closeAndRestore(reader, rig.proxy)

            // the re-declaration ends with RAISE of the instance's declaration count (deleted by the reclaim)
            val declared = rig.keys.instanceDeclared(rig.readerCore.instanceId)
            val pace = CountDownLatch(1) // never counted down: a bounded pause between looks
            var looks = 0
            while (!rig.raw.exists(declared) && looks++ < 2000) pace.await(10, TimeUnit.MILLISECONDS)
            assertTrue(rig.raw.exists(declared), "the reader's process did not declare again")

            (4..10).forEach { rig.publisher.publishAll(rig.numbers, listOf(it)) }
            val whileRunning = state(rig.raw, rig.readers, list)
            rig.readerCore.close()
            val afterCoreClose = state(rig.raw, rig.readers, list)
            val clean = "in reader set: false, list length: 0"
            assertTrue(
                whileRunning == clean && afterCoreClose == clean,
                "a closed reader is still registered and filled by publishes. While its core runs: $whileRunning; " +
                    "after its core closed: $afterCoreClose",
            )
        }
    }

    private fun state(raw: Jedis, readers: ByteArray, list: ByteArray): String =
        "in reader set: ${raw.sismember(readers, list)}, list length: ${raw.llen(list)}"
}

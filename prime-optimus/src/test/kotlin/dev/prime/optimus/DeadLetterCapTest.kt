package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.ErrorHandler
import dev.prime.EventBlock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import redis.clients.jedis.args.ListDirection
import java.net.URI
import java.time.Duration
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/** Dead letters are capped (older ones trimmed and counted); reply lists get an expiry whenever a reply is pushed. */
class DeadLetterCapTest {

    @Test
    fun deadLettersAreCappedAndTheTrimmedOnesCounted() {
        val failed = CountDownLatch(5)
        OptimusCore.builder().config(CoreConfig.builder().errorHandler(ErrorHandler { _, _, _ -> failed.countDown() }).build())
            .redis(TestRedis.url).deadLetterLimit(3).build().use { core ->
                val events = EventBlock<Int>()
                core.source("numbers", events).then(core.chain("refuse") { x: Int -> throw IllegalArgumentException("bad $x") })
                core.start()
                (1..5).forEach(events::publish)
                assertTrue(failed.await(20, TimeUnit.SECONDS))
                val deadline = System.nanoTime() + Duration.ofSeconds(20).toNanos()
                while (core.trimmedDeadLetters("refuse") < 2 && System.nanoTime() < deadline) Thread.sleep(10)
                assertEquals(2L, core.trimmedDeadLetters("refuse"))
                val reasons = core.deadLetters("refuse").map { it.reason }
                assertEquals(3, reasons.size, reasons.toString())
                assertTrue(reasons.map { it.substringAfterLast("bad ") }.containsAll(listOf("3", "4", "5")), reasons.toString())
            }
    }

    @Test
    fun clearingDeadLettersKeepsTheTrimmedCountAndALetterHandsOutCopies() {
        OptimusCore.builder().redis(TestRedis.url).deadLetterLimit(2).build().use { core ->
            val events = EventBlock<Int>()
            val out = core.source("numbers", events).then(core.chain("strict") { x: Int -> x + 1 }).reader()
            core.start()
            Jedis(URI(TestRedis.url)).use { raw -> repeat(3) { raw.rpush(core.keys.serviceInput("strict"), "garbage $it".toByteArray()) } }
            events.publish(1) // behind the 3 bad entries: once it is out, they were handled
            assertEquals(2, out.take(Duration.ofSeconds(20)).orElseThrow())
            assertEquals(1L, core.trimmedDeadLetters("strict"))
            val letter = core.deadLetters("strict").first()
            letter.bytes().fill(0)
            assertEquals("garbage 1", String(letter.bytes()), "bytes() is a copy: changing one changes not the letter")

            assertEquals(2, core.clearDeadLetters("strict"))
            assertEquals(emptyList<DeadLetter>(), core.deadLetters("strict"))
            assertEquals(1L, core.trimmedDeadLetters("strict"), "clearing the dead letters does not reset the trimmed count")
        }
    }

    @Test
    fun aReplyListExpiresAfterTwiceACallTimeoutLongerThanFiveMinutes() {
        val ttl = replyListTtl(OptimusCore.builder().redis(TestRedis.url).callTimeout(Duration.ofMinutes(20)), 78L)
        val expected = Duration.ofMinutes(40).toMillis()
        assertTrue(ttl in (expected - 60_000)..expected, "the reply list expires in $ttl ms, not twice the 20 min call timeout")
    }

    @Test
    fun aReplyListGetsAnExpiryWhenAReplyIsPushed() {
        val ttl = replyListTtl(OptimusCore.builder().redis(TestRedis.url), 77L)
        assertTrue(ttl in 1..Duration.ofMinutes(10).toMillis(), "the reply list expires in $ttl ms")
    }

    /** Pushes request [id] to an echo service of a core [builder] makes and returns its reply list's expiry, in ms. */
    private fun replyListTtl(builder: OptimusCore.Builder, id: Long): Long =
        builder.build().use { core ->
            core.chain("echo") { x: Int -> x }.toBlock()
            core.start()
            val reply = core.keys.reply("a-caller-$id")
            Jedis(URI(TestRedis.url)).use { raw ->
                raw.rpush(core.keys.serviceInput("echo"), Envelope.request(id, reply, core.encode(5)))
                assertTrue(raw.blmove(reply, reply, ListDirection.LEFT, ListDirection.RIGHT, 20.0) != null, "no reply")
                raw.pttl(reply)
            }
        }
}

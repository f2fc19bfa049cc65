package dev.prime.optimus

import dev.prime.CoreClosedException
import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.Tick
import dev.prime.Tuple2
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.time.Duration
import java.time.Instant
import java.util.Optional
import java.util.UUID

/**
 * `publishAll` refuses a null value, a source of another core and a service's output with
 * `IllegalArgumentException`, publishing nothing; an empty iterable publishes nothing; before
 * `start()` it is refused with `IllegalStateException`, and after `close()` with
 * `CoreClosedException`, whatever the values.
 */
class PublishAllTest {

    @Test
    fun aNullAmongTheValuesIsRefusedAndNothingIsPublished() {
        TestRedis.core(named()).use { core ->
            val numbers = core.source("numbers", EventBlock<Int?>())
            val reader = numbers.reader()
            core.start()
            val refused = assertThrows(IllegalArgumentException::class.java) { core.publishAll(numbers, listOf(1, null, 3)) }
            assertTrue("null" in refused.message!!, refused.message)
            assertEquals(Optional.empty<Int>(), reader.poll(), "the value before the null was not published")
            core.publishAll(numbers, listOf(4))
            assertEquals(listOf(4), reader.drain())
        }
    }

    /**
     * Called from Java, a `null` source or a `null` values is refused with a [NullPointerException]
     * that names the parameter and says what to pass, as the core's other declarations refuse a
     * `null`, not with the message Kotlin makes for a non-null parameter; nothing is published.
     */
    @Test
    fun aNullSourceOrValuesFromJavaIsRefusedNamingIt() {
        TestRedis.core(named()).use { core ->
            val numbers = core.source("numbers", EventBlock<Int?>())
            val reader = numbers.reader()
            core.start()
            val publishAll = OptimusCore::class.java.getMethod("publishAll", dev.prime.Source::class.java, Iterable::class.java)
            val fromJava = { source: Any?, values: Any? ->
                try {
                    publishAll.invoke(core, source, values)
                    null
                } catch (e: java.lang.reflect.InvocationTargetException) {
                    e.cause
                }
            }
            val noSource = fromJava(null, listOf(1))
            assertTrue(noSource is NullPointerException, "a null source: $noSource")
            assertTrue(
                "source must not be null" in noSource!!.message!! && "core.source(events)" in noSource.message!!,
                noSource.message,
            )
            val noValues = fromJava(numbers, null)
            assertTrue(noValues is NullPointerException, "a null values: $noValues")
            assertTrue(
                "values must not be null" in noValues!!.message!! && "empty list" in noValues.message!!,
                noValues.message,
            )
            val nullValue = assertThrows(IllegalArgumentException::class.java) { core.publishAll(numbers, listOf(1, null, 3)) }
            assertTrue(
                "value 1 of values is null" in nullValue.message!! && "Optional" in nullValue.message!!,
                nullValue.message,
            )
            assertEquals(Optional.empty<Int?>(), reader.poll(), "nothing was published")
        }
    }

    @Test
    fun aSourceOfAnotherCoreIsRefused() {
        TestRedis.core(named()).use { mine ->
            TestRedis.core(named()).use { other ->
                val foreign = other.source("numbers", EventBlock<Int>())
                mine.start()
                val refused = assertThrows(IllegalArgumentException::class.java) { mine.publishAll(foreign, listOf(1)) }
                assertTrue("is not a source of" in refused.message!!, refused.message)
            }
        }
    }

    /**
     * A source made by a service (a chain linked to a source, a filter) is published only by that
     * service: `publishAll` to it is refused, says to publish to the event block's source, and
     * publishes nothing.
     */
    @Test
    fun aServicesOutputIsRefusedAndNothingIsPublished() {
        TestRedis.core(named()).use { core ->
            val numbers = core.source("numbers", EventBlock<Int>())
            val doubled = numbers.then(core.chain("double") { x: Int -> 2 * x })
            val even = numbers.filter { it % 2 == 0 }
            val fromDoubled = doubled.reader()
            val fromEven = even.reader()
            core.start()
            for (output in listOf(doubled, even)) {
                val refused = assertThrows(IllegalArgumentException::class.java) { core.publishAll(output, listOf(100, 200)) }
                val message = refused.message!!
                assertTrue("'${output.name()}'" in message && "output of a service" in message, message)
                assertTrue("event block's source" in message, "says how to fix it: $message")
            }
            core.publishAll(numbers, listOf(2))
            assertEquals(4, fromDoubled.take(PATIENCE).orElseThrow(), "the refused values were not published")
            assertEquals(2, fromEven.take(PATIENCE).orElseThrow(), "the refused values were not published")
            assertEquals(emptyList<Int>(), fromDoubled.drain() + fromEven.drain())
        }
    }

    /**
     * A source the core publishes to itself (a combinator's output, a timer) is refused the same
     * way: no event block the program holds publishes to it.
     */
    @Test
    fun aCombinatorsOrATimersOutputIsRefusedAndNothingIsPublished() {
        TestRedis.core(named()).use { core ->
            val numbers = core.source("numbers", EventBlock<Int>())
            val letters = core.source("letters", EventBlock<String>())
            val latest = numbers.withLatestFrom(letters)
            val ticks = core.timer("ticks", Duration.ofHours(1))
            val fromLatest = latest.reader()
            val fromTicks = ticks.reader()
            core.start()
            val refused = assertThrows(IllegalArgumentException::class.java) {
                core.publishAll(latest, listOf(Tuple2(1, "a")))
            }
            assertTrue("'${latest.name()}'" in refused.message!! && "event block's source" in refused.message!!, refused.message)
            val tick = assertThrows(IllegalArgumentException::class.java) { core.publishAll(ticks, listOf(Tick(1L, Instant.EPOCH))) }
            assertTrue("'ticks'" in tick.message!!, tick.message)
            assertEquals(Optional.empty<Tuple2<Int, String>>(), fromLatest.poll(), "the refused value was not published")
            assertEquals(Optional.empty<Tick>(), fromTicks.poll(), "the refused tick was not published")
        }
    }

    /** An empty iterable publishes nothing once started, and is refused before start() as any publish. */
    @Test
    fun anEmptyIterablePublishesNothingAndIsRefusedBeforeStart() {
        TestRedis.core(named()).use { core ->
            val numbers = core.source("numbers", EventBlock<Int>())
            val reader = numbers.reader()
            val early = assertThrows(IllegalStateException::class.java) { core.publishAll(numbers, emptyList()) }
            assertTrue("start()" in early.message!! && core.name() in early.message!!, early.message)
            core.start()
            core.publishAll(numbers, emptyList())
            core.publishAll(numbers, listOf(1))
            assertEquals(listOf(1), listOf(reader.take(PATIENCE).orElseThrow()) + reader.drain())
        }
    }

    /** After close(), publishAll is refused with CoreClosedException, also for an empty iterable. */
    @Test
    fun aClosedCoreRefusesEveryPublishAll() {
        val core = TestRedis.core(named())
        val numbers = core.source("numbers", EventBlock<Int>())
        core.start()
        core.close()
        assertThrows(CoreClosedException::class.java) { core.publishAll(numbers, listOf(1)) }
        assertThrows(CoreClosedException::class.java) { core.publishAll(numbers, emptyList()) }
    }

    /**
     * Kotlin callers keep non-null types: a call with a `Source<T>?` does not resolve to the
     * member `publishAll`, which takes a non-null source and non-null values, but to this file's
     * extension of the same name taking nullable ones (a member wins over an extension whenever it
     * applies); the refusal of a Java `null` is another method's, which Kotlin does not see.
     */
    @Test
    fun kotlinCallersSeeNonNullParameters() {
        TestRedis.core(named()).use { core ->
            val numbers: dev.prime.Source<Int>? = core.source("numbers", EventBlock<Int>())
            val maybeValues: Iterable<Int>? = listOf(1)
            core.start()
            val resolved: Any = core.publishAll(numbers, listOf(1))
            assertEquals(NULLABLE_EXTENSION, resolved, "a call with a Source<Int>? resolved to the member")
            val resolvedForValues: Any = core.publishAll(numbers!!, maybeValues)
            assertEquals(NULLABLE_EXTENSION, resolvedForValues, "a call with an Iterable<Int>? resolved to the member")
        }
    }

    private fun named(): CoreConfig = CoreConfig.builder().name("publish-all-" + UUID.randomUUID()).build()

    private companion object {
        const val NULLABLE_EXTENSION = "the extension taking nullable parameters"
        val PATIENCE: Duration = Duration.ofSeconds(20)
    }
}

/** Chosen by a call of `publishAll` with a nullable argument only if the member takes none. */
@Suppress("UNUSED_PARAMETER", "EXTENSION_SHADOWED_BY_MEMBER") // shadowed only if the member took nullable ones
private fun <T> OptimusCore.publishAll(source: dev.prime.Source<T>?, values: Iterable<T>?): String =
    "the extension taking nullable parameters"

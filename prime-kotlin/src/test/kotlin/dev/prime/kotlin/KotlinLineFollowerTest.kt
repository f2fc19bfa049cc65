package dev.prime.kotlin

import dev.prime.CoreConfig
import dev.prime.VirtualClock
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.nio.file.Files
import java.nio.file.Path
import java.time.Duration

internal class KotlinLineFollowerTest {

    /**
     * Two virtual seconds stepped one gyro period at a time: every gyro reading from the first
     * fused one on steers exactly once, with a line reading no newer than it (the line chain runs
     * as its own service, so the latest one it finished, not always the latest due); the turn
     * rate is the PD law's.
     */
    @Test
    fun `every gyro reading after the first line reading steers once with a line reading no newer than it`() {
        for (media in listOf(Liberty, Radiant)) {
            val clock = VirtualClock()
            val commands = mutableListOf<Steering>()
            media.newCore(CoreConfig.builder().clock(clock).build()).use { core ->
                val steering = KotlinLineFollower.declare(core).reader()
                core.start()
                for (step in 1L..200L) {
                    clock.advance(Duration.ofMillis(10))
                    val now = step * 10
                    // Gyro readings before the first line reading are dropped: look briefly.
                    if (commands.isEmpty()) steering.take(Duration.ofMillis(20)).ifPresent(commands::add)
                    // From then on every gyro reading gives one command: wait for it.
                    while (commands.isNotEmpty() && commands.last().gyroMillis < now) {
                        val command = steering.take(Duration.ofSeconds(20))
                        assertTrue(command.isPresent, "$media: no steering command at $now ms")
                        commands += command.get()
                    }
                }
            }
            val first = commands.first().gyroMillis
            assertTrue(first >= 50, "$media: nothing fuses before the first line reading (50 ms): $first")
            assertEquals((2_000 - first) / 10 + 1, commands.size.toLong(), "$media: one command per gyro reading")
            commands.forEachIndexed { i, c ->
                assertEquals(first + 10L * i, c.gyroMillis, "$media: gyro readings in order, none twice")
                assertTrue(c.lineMillis % 50 == 0L && c.lineMillis in 50..c.gyroMillis, "$media: never a line reading from the future: $c")
                val expected = 2.0 * KotlinLineFollower.lineAt(c.lineMillis).offset -
                    0.3 * KotlinLineFollower.gyroAt(c.gyroMillis).yawRate
                assertEquals(expected, c.turnRate, 1e-12, "$media: $c")
            }
        }
    }

    /** The README shows the code between the markers of KotlinLineFollower.kt, unindented, verbatim. */
    @Test
    fun `the README shows the compiled Kotlin sensor fusion`() {
        val source = Files.readString(Path.of("src/test/kotlin/dev/prime/kotlin/KotlinLineFollower.kt"))
        val readme = Files.readString(Path.of("../README.md"))
        val begin = "// kotlin-fusion:begin\n"
        val end = "        // kotlin-fusion:end"
        val body = source.substring(source.indexOf(begin) + begin.length, source.indexOf(end))
        val snippet = body.lines().dropLast(1).joinToString("") { it.drop(8) + "\n" }
        assertTrue(readme.contains("```kotlin\n$snippet```"), "README.md must show KotlinLineFollower.kt's snippet, unindented by 8:\n$snippet")
    }
}

package dev.prime.kotlin

import kotlinx.coroutines.runBlocking
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.io.ByteArrayOutputStream
import java.io.PrintStream
import java.nio.charset.StandardCharsets.UTF_8
import java.nio.file.Files
import java.nio.file.Path

internal class KotlinQuickStartTest {

    @Test
    fun `prints what its comments say`() = runBlocking {
        val out = ByteArrayOutputStream()
        KotlinQuickStart.run(PrintStream(out, true, UTF_8))
        assertEquals(listOf("[70.7 F, 71.6 F, 74.3 F]", "212.0", "null"), out.toString(UTF_8).lines().filter(String::isNotEmpty))
    }

    /** The README shows the code between the markers of KotlinQuickStart.kt, unindented, verbatim. */
    @Test
    fun `the README shows the compiled Kotlin quick start`() {
        val source = Files.readString(Path.of("src/test/kotlin/dev/prime/kotlin/KotlinQuickStart.kt"))
        val readme = Files.readString(Path.of("../README.md"))
        val begin = "// kotlin-quick-start:begin\n"
        val end = "        // kotlin-quick-start:end"
        val body = source.substring(source.indexOf(begin) + begin.length, source.indexOf(end))
        val snippet = body.lines().dropLast(1).joinToString("") { it.drop(8) + "\n" }
        assertTrue(readme.contains("```kotlin\n$snippet```"), "README.md must show KotlinQuickStart.kt's snippet, unindented by 8:\n$snippet")
    }
}

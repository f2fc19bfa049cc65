package dev.prime.kotlin

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import org.w3c.dom.Element
import java.nio.file.Path
import javax.xml.parsers.DocumentBuilderFactory

/**
 * The README's "Kotlin": prime-kotlin needs only prime-core and kotlinx-coroutines (and Kotlin's
 * standard library), so a Liberty-only Kotlin project pulls no Redis. Read from this module's pom
 * (the parent adds no dependencies).
 */
internal class DependenciesTest {

    @Test
    fun `needs only the core, the Kotlin library and kotlinx-coroutines`() {
        val project = DocumentBuilderFactory.newInstance().newDocumentBuilder().parse(Path.of("pom.xml").toFile()).documentElement
        val dependencies = project.childElements().single { it.tagName == "dependencies" }
        val needed = dependencies.childElements()
            .filter { it.tagName == "dependency" && it.text("scope") != "test" }
            .map { "${it.text("groupId")}:${it.text("artifactId")}" + if (it.text("optional") == "true") " (optional)" else "" }
        assertEquals(
            listOf("dev.prime:prime-core", "org.jetbrains.kotlin:kotlin-stdlib", "org.jetbrains.kotlinx:kotlinx-coroutines-core-jvm"),
            needed,
        )
    }

    private fun Element.childElements(): List<Element> =
        (0 until childNodes.length).map { childNodes.item(it) }.filterIsInstance<Element>()

    private fun Element.text(name: String): String? = childElements().firstOrNull { it.tagName == name }?.textContent?.trim()
}

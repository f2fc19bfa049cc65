package dev.prime.kotlin

import dev.prime.Source
import java.lang.module.ModuleDescriptor
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/** prime-kotlin is the named module `dev.prime.kotlin` (its tests run on the module path). */
class KotlinModuleTest {

    @Test
    fun theModuleExportsItsOnePackage() {
        val module = Class.forName("dev.prime.kotlin.SourceFlowsKt").module
        assertTrue(module.isNamed, "the tests run prime-kotlin as a named module")
        assertEquals("dev.prime.kotlin", module.name)
        assertFalse(module.descriptor.isOpen)
        assertEquals(setOf("dev.prime.kotlin"), module.descriptor.exports().map(ModuleDescriptor.Exports::source).toSet())
        assertTrue(module.canRead(Source::class.java.module), "it reads dev.prime")
    }
}

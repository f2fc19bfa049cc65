package dev.prime.optimus

import java.lang.module.ModuleDescriptor
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/**
 * prime-optimus is the named module `dev.prime.optimus` (its tests run on the module path): it
 * exports its API package only, not its Kryo codec's internals, and reads the core's internals,
 * which the core exports to it alone.
 */
class OptimusModuleTest {

    @Test
    fun theModuleExportsItsApiOnly() {
        val module = OptimusCore::class.java.module
        assertTrue(module.isNamed, "the tests run prime-optimus as a named module")
        assertEquals("dev.prime.optimus", module.name)
        val descriptor = module.descriptor
        assertFalse(descriptor.isOpen)
        assertEquals(setOf("dev.prime.optimus"), descriptor.exports().map(ModuleDescriptor.Exports::source).toSet())
        assertTrue("dev.prime.optimus.kryo" in module.packages)
        assertFalse(module.isExported("dev.prime.optimus.kryo"))
    }

    @Test
    fun theCoreExportsItsInternalsToOptimusAlone() {
        val core = dev.prime.PrimeCore::class.java.module
        assertTrue(core.isExported("dev.prime.internal", OptimusCore::class.java.module))
        assertFalse(core.isExported("dev.prime.internal"))
    }
}

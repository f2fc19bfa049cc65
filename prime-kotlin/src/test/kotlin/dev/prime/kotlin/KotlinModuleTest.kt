package dev.prime.kotlin

import java.io.File
import java.lang.module.Configuration
import java.lang.module.ModuleDescriptor
import java.lang.module.ModuleFinder
import java.nio.file.Files
import java.nio.file.Path
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/**
 * prime-kotlin is the named module `dev.prime.kotlin`. Its tests run on the class path (they run
 * every media), so this test resolves the module from the compiled classes and the jars of its
 * dependencies, in a module layer of its own: it exports its one package, and its classes load
 * and link there (reading the core and kotlinx.coroutines as modules).
 */
class KotlinModuleTest {

    @Test
    fun theModuleResolvesExportsItsOnePackageAndLoads() {
        val entries = System.getProperty("java.class.path").split(File.pathSeparator)
            .map(Path::of)
            .filter { Files.exists(it) && !it.toString().contains("test-classes") && !it.toString().endsWith("-tests.jar") }
        val parent = ModuleLayer.boot()
        val configuration = Configuration.resolve(
            ModuleFinder.of(*entries.toTypedArray()), listOf(parent.configuration()), ModuleFinder.of(), setOf("dev.prime.kotlin"),
        )
        val layer = parent.defineModulesWithOneLoader(configuration, ClassLoader.getPlatformClassLoader())
        val module = layer.findModule("dev.prime.kotlin").orElseThrow()
        assertFalse(module.descriptor.isOpen)
        assertEquals(setOf("dev.prime.kotlin"), module.descriptor.exports().map(ModuleDescriptor.Exports::source).toSet())
        val flows = layer.findLoader("dev.prime.kotlin").loadClass("dev.prime.kotlin.SourceFlows")
        assertEquals("dev.prime.kotlin", flows.module.name)
        assertTrue(flows.declaredMethods.any { it.name == "asFlow" }, "the class links against the core and coroutines")
    }
}

package dev.prime.optimus

import dev.prime.Tuple2
import java.io.File
import java.lang.module.Configuration
import java.lang.module.ModuleDescriptor
import java.lang.module.ModuleFinder
import java.nio.file.Files
import java.nio.file.Path
import org.junit.jupiter.api.Assertions.assertArrayEquals
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/**
 * prime-optimus is the named module `dev.prime.optimus`. Its tests run on the class path (several
 * start worker JVMs from it), so this test resolves the module itself: from the compiled classes
 * and the jars of its dependencies, in a module layer of its own, where it exports its API package
 * only, reads the core's internals (exported to it alone), and its codec encodes and decodes a
 * record of the core (Kryo reading `dev.prime` as a module).
 */
class OptimusModuleTest {

    /** A layer holding dev.prime.optimus and what it requires, found on this test's class path. */
    private fun layer(): ModuleLayer {
        val entries = System.getProperty("java.class.path").split(File.pathSeparator)
            .map(Path::of)
            .filter { Files.exists(it) && !it.toString().contains("test-classes") && !it.toString().endsWith("-tests.jar") }
        val finder = ModuleFinder.of(*entries.toTypedArray())
        val parent = ModuleLayer.boot()
        val configuration = Configuration.resolve(finder, listOf(parent.configuration()), ModuleFinder.of(), setOf("dev.prime.optimus"))
        return parent.defineModulesWithOneLoader(configuration, ClassLoader.getPlatformClassLoader())
    }

    @Test
    fun theModuleResolvesAndExportsItsApiOnly() {
        val layer = layer()
        val optimus = layer.findModule("dev.prime.optimus").orElseThrow()
        val descriptor = optimus.descriptor
        assertFalse(descriptor.isOpen)
        assertEquals(setOf("dev.prime.optimus"), descriptor.exports().map(ModuleDescriptor.Exports::source).toSet())
        assertTrue("dev.prime.optimus.kryo" in optimus.packages)
        assertFalse(optimus.isExported("dev.prime.optimus.kryo"))
        val core = layer.findModule("dev.prime").orElseThrow()
        assertTrue(core.isExported("dev.prime.internal", optimus), "the core's internals are exported to Optimus")
        assertFalse(core.isExported("dev.prime.internal"), "and to nobody else")
    }

    @Test
    fun theCodecRunsAsAModule() {
        val layer = layer()
        val loader = layer.findLoader("dev.prime.optimus")
        val codecClass = loader.loadClass("dev.prime.optimus.KryoCodec")
        assertEquals("dev.prime.optimus", codecClass.module.name)
        val codec = codecClass.getMethod("standard").invoke(null)
        val tupleClass = loader.loadClass(Tuple2::class.java.name)
        assertEquals("dev.prime", tupleClass.module.name)
        val tuple = tupleClass.getConstructor(Any::class.java, Any::class.java).newInstance(7, "seven")
        val encode = codecClass.getMethod("encode", Any::class.java)
        val bytes = encode.invoke(codec, tuple) as ByteArray
        val decoded = codecClass.getMethod("decode", ByteArray::class.java).invoke(codec, bytes)
        assertEquals(tuple, decoded)
        assertArrayEquals(bytes, encode.invoke(codec, decoded) as ByteArray)
    }
}

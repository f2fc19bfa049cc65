package dev.prime.optimus

import dev.prime.optimus.kryo.AllowList
import org.junit.jupiter.api.Assertions.assertArrayEquals
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNotSame
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.net.URL
import java.net.URLClassLoader
import java.nio.file.Files
import java.nio.file.Path
import javax.tools.ToolProvider

/**
 * Ids that depend on nothing but the allow-list: the same in another class loader (a process of
 * its own, as far as classes go) that met the types in another order, and a hash collision
 * detected instead of resolved by order.
 */
internal class KryoCodecIdentityTest {

    /** The code locations the codec and the test types need, for a loader that shares nothing. */
    private fun isolatedLoader(): URLClassLoader {
        val anchors = listOf(
            "dev.prime.optimus.KryoCodec", "dev.prime.Token", "com.esotericsoftware.kryo.Kryo",
            "org.objenesis.Objenesis", "com.esotericsoftware.minlog.Log", "com.esotericsoftware.reflectasm.ConstructorAccess",
            "kotlin.Unit", "dev.prime.optimus.CrossLoaderProbe",
        )
        val urls = anchors.mapNotNull { name ->
            runCatching { Class.forName(name).protectionDomain.codeSource?.location }.getOrNull()
        }.distinct()
        return URLClassLoader(urls.toTypedArray<URL>(), ClassLoader.getPlatformClassLoader())
    }

    @Test
    fun `another class loader meeting the types in another order writes the same bytes under the same fingerprint`() {
        isolatedLoader().use { loader ->
            val probe = loader.loadClass(CrossLoaderProbe::class.java.name)
            assertNotSame(CrossLoaderProbe::class.java, probe)
            val values = CrossLoaderProbe.values()
            val forward = IntArray(values.size) { it }
            @Suppress("UNCHECKED_CAST")
            val theirs = probe.getMethod("encode", IntArray::class.java).invoke(null, forward) as List<Any>

            // here: the same codec, types first met in the reverse order
            val mine = CrossLoaderProbe.encode(forward.reversedArray())
            assertEquals(mine[0], theirs[0], "fingerprint")
            for (i in values.indices) {
                assertArrayEquals(mine[i + 1] as ByteArray, theirs[i + 1] as ByteArray, values[i].toString())
            }
            val reader = CrossLoaderProbe.codec()
            reader.encode(values.last()) // the learned record: readable once sent here
            for (i in values.indices) assertEquals(values[i], reader.decode(theirs[i + 1] as ByteArray), values[i].toString())
        }
    }

    @Test
    fun `two classes of an allowed package with the same hash id are refused, writing and reading`(@TempDir dir: Path) {
        val (first, second) = collidingNames("gen.collide.T")
        val sources = listOf(first, second).map { name ->
            val simple = name.substringAfterLast('.')
            val file = dir.resolve("src/$simple.java")
            Files.createDirectories(file.parent)
            Files.writeString(file, "package gen.collide; public record $simple(int value) {}")
            file.toString()
        }
        val classes = dir.resolve("classes")
        val compiler = ToolProvider.getSystemJavaCompiler()
        assertEquals(0, compiler.run(null, null, null, "-d", classes.toString(), *sources.toTypedArray()), "javac")

        URLClassLoader(arrayOf(classes.toUri().toURL()), javaClass.classLoader).use { loader ->
            val thread = Thread.currentThread()
            val previous = thread.contextClassLoader
            thread.contextClassLoader = loader
            val (writer, reader) = try {
                List(2) { KryoCodec.builder().learnRecordsAndEnums(false).allowPackage("gen.collide").build() }
            } finally {
                thread.contextClassLoader = previous
            }
            fun instance(name: String): Any = loader.loadClass(name).getConstructor(Int::class.java).newInstance(7)
            val bytes = writer.encode(instance(first))
            val e = assertThrows(IllegalArgumentException::class.java) { writer.encode(instance(second)) }
            val expected = "$second and $first have the same KryoCodec id ${AllowList.hashId(first)}"
            assertTrue(e.message!!.contains(expected), e.message)

            val refused = assertThrows(CodecException::class.java) { reader.decode(bytes) }
            assertTrue(refused.message!!.contains("have the same KryoCodec id ${AllowList.hashId(first)}"), refused.message)
        }
    }

    /** Two class names under [prefix] whose hash ids are equal (a birthday search, bounded). */
    private fun collidingNames(prefix: String): Pair<String, String> {
        val seen = HashMap<Int, String>()
        for (n in 0 until 1_000_000) {
            val name = "$prefix$n"
            val other = seen.putIfAbsent(AllowList.hashId(name), name)
            if (other != null) return other to name
        }
        throw AssertionError("no collision among a million names: the id space is larger than documented")
    }
}

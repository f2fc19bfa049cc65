package dev.prime.optimus.kryo

import java.io.File
import java.io.IOException
import java.net.JarURLConnection
import java.net.URISyntaxException
import java.net.URL

/**
 * The names of the classes of one package, as a class loader's directories and jars list them,
 * without loading any class. Subpackages are not included. Locations other than directories and
 * jars (a module image, a custom URL scheme) are skipped: a class there is not found by its hash
 * and must be allowed by class.
 */
internal object PackageClassNames {

    fun list(packageName: String, loader: ClassLoader): List<String> {
        val path = packageName.replace('.', '/')
        val names = sortedSetOf<String>()
        for (url in loader.getResources(path)) {
            try {
                when (url.protocol) {
                    "file" -> inDirectory(url, names, packageName)
                    "jar" -> inJar(url, path, names)
                }
            } catch (e: IOException) {
                continue // unreadable location: its classes are not found by hash
            } catch (e: URISyntaxException) {
                continue
            }
        }
        return names.filter { !it.endsWith(".package-info") && !it.endsWith(".module-info") }
    }

    private fun inDirectory(url: URL, names: MutableSet<String>, packageName: String) {
        File(url.toURI()).listFiles()?.forEach { file ->
            if (file.isFile && file.name.endsWith(CLASS)) names += packageName + "." + file.name.removeSuffix(CLASS)
        }
    }

    private fun inJar(url: URL, path: String, names: MutableSet<String>) {
        val connection = url.openConnection() as JarURLConnection
        connection.useCaches = false
        connection.jarFile.use { jar ->
            for (entry in jar.entries()) {
                val name = entry.name
                if (name.startsWith("$path/") && name.endsWith(CLASS) && name.indexOf('/', path.length + 1) < 0) {
                    names += name.removeSuffix(CLASS).replace('/', '.')
                }
            }
        }
    }

    private const val CLASS = ".class"
}

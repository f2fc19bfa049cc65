package dev.prime.optimus

/**
 * Run by [EmbeddedRedisDependencyTest] in a JVM whose class path lacks
 * `dev.prime:prime-redis-embedded`: `new OptimusCore()` with no Redis URL, printing `STARTED` if
 * it started a Redis, else `FAILED <exception class>: <message>` on one line.
 */
object NoEmbeddedRedisMain {
    @JvmStatic
    fun main(args: Array<String>) {
        try {
            OptimusCore().use { println("STARTED") }
        } catch (e: Exception) {
            println("FAILED ${e.javaClass.name}: ${e.message?.replace('\n', ' ')}")
        }
    }
}

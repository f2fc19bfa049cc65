package dev.prime.optimus

import dev.prime.CoreConfig
import redis.clients.jedis.Jedis
import redis.clients.jedis.params.ScanParams

/**
 * One embedded Redis for the tests of this JVM (each core is its own namespace on it), or the
 * Redis at the `PRIME_TEST_REDIS` URL when set. Its shutdown hook stops it when the JVM exits.
 */
internal object TestRedis {
    private val embedded: EmbeddedRedis? by lazy {
        if (System.getenv("PRIME_TEST_REDIS") != null) null else EmbeddedRedis.start()
    }

    val url: String get() = System.getenv("PRIME_TEST_REDIS") ?: embedded!!.uri

    /** The values in the Redis [list] (an entry may be a frame of many). */
    fun values(jedis: Jedis, list: ByteArray): Long = jedis.lrange(list, 0, -1).sumOf { Frame.count(it).toLong() }

    /** Every key of [topology] (`prime:{topology}:*`) on the server [jedis] talks to, by `SCAN`. */
    fun keysOf(jedis: Jedis, topology: String): List<String> {
        val params = ScanParams().match("prime:{$topology}:*").count(1000)
        var cursor = ScanParams.SCAN_POINTER_START
        val found = ArrayList<String>()
        repeat(10_000) {
            val page = jedis.scan(cursor, params)
            found += page.result
            cursor = page.cursor
            if (cursor == ScanParams.SCAN_POINTER_START) return found
        }
        throw AssertionError("SCAN did not finish")
    }

    fun core(config: CoreConfig = CoreConfig.defaults()): OptimusCore =
        OptimusCore.builder().config(config).redis(url).build()
}

package dev.prime.optimus

import dev.prime.CoreConfig

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
    fun values(jedis: redis.clients.jedis.Jedis, list: ByteArray): Long = jedis.lrange(list, 0, -1).sumOf { Frame.count(it).toLong() }

    fun core(config: CoreConfig = CoreConfig.defaults()): OptimusCore =
        OptimusCore.builder().config(config).redis(url).build()
}

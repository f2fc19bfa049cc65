package dev.prime.optimus

import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.Source

/**
 * Runs [test] with a publisher core on an embedded Redis, its started source `numbers`, a
 * [FaultProxy] in front of that Redis and a second core of the same topology (named [name] plus a
 * nonce) reached through the proxy, not started: the test declares its reader there and starts it.
 * Both cores host nothing; everything is closed when [test] returns.
 */
internal fun withProxiedReaderCore(
    name: String,
    test: (publisher: OptimusCore, numbers: Source<Int>, proxy: FaultProxy, readerCore: OptimusCore) -> Unit,
) {
    val config = CoreConfig.builder().name("$name-${System.nanoTime()}").build()
    EmbeddedRedis.start().use { redis ->
        FaultProxy(redis.uri).use { proxy ->
            OptimusCore.builder().config(config).redis(redis.uri).hosts(emptyList()).build().use { publisher ->
                val numbers = publisher.source("numbers", EventBlock<Int>())
                publisher.start()
                OptimusCore.builder().config(config).redis(proxy.url).hosts(emptyList()).build().use { readerCore ->
                    test(publisher, numbers, proxy, readerCore)
                }
            }
        }
    }
}

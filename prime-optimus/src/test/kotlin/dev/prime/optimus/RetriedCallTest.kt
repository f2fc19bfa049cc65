package dev.prime.optimus

import dev.prime.CoreConfig
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import java.time.Duration
import java.util.concurrent.ConcurrentHashMap
import java.util.concurrent.atomic.AtomicInteger

/**
 * A call whose connection breaks after its request reached Redis is retried; the retry must not
 * lose the reply the service pushed meanwhile (the service skips the resent request as a
 * duplicate, so that reply is the only one).
 */
class RetriedCallTest {

    @Test
    fun aCallRetriedAfterItsRequestArrivedStillGetsItsReply() {
        val calls = 8
        val ran = ConcurrentHashMap<Int, AtomicInteger>()
        val name = "retried-${System.nanoTime()}"
        val config = CoreConfig.builder().name(name).build()
        // the worker hosts the service on a direct connection; the caller goes through the proxy
        OptimusCore.builder().config(config).redis(TestRedis.url).hosts("work").build().use { worker ->
            worker.chain("work") { x: Int -> ran.computeIfAbsent(x) { AtomicInteger() }.incrementAndGet(); x * 10 }.toBlock()
            worker.start()
            FaultProxy(TestRedis.url).use { proxy ->
                OptimusCore.builder().config(config).redis(proxy.url).hosts(emptyList()).callTimeout(Duration.ofSeconds(5))
                    .build().use { caller ->
                        val work = caller.chain("work") { x: Int -> x }.toBlock()
                        caller.start()
                        proxy.cutAfterWritesContaining(String(caller.keys.serviceInput("work")))
                        val results = (1..calls).map { runCatching { work.process(it) } }
                        assertEquals((1..calls).map { Result.success(it * 10) }, results, "every call returns its result")
                        assertEquals((1..calls).associateWith { 1 }, ran.mapValues { it.value.get() }, "each call ran once")
                        assertEquals(calls, proxy.cuts.get(), "every call's first request write was cut")
                    }
            }
        }
    }
}

package dev.prime.optimus

import dev.prime.EventBlock
import redis.clients.jedis.Jedis
import java.net.URI
import java.util.concurrent.CountDownLatch

/**
 * Run by [EmbeddedRedisJvmEndTest] in a JVM of its own: starts an [OptimusCore] on its
 * embedded Redis and never closes it. Prints `READY <redis pid> <redis working directory>`, then
 * returns from `main` when it reads a line from its standard input (or the input ends), or, with
 * the argument `wait`, waits until the test signals it (`Process.destroy()` closes the child's
 * input before it sends SIGTERM, so a child reading its input could end before the signal).
 * With the argument `crashed` it starts an [EmbeddedRedis] of its own instead, never closed, and
 * kills its server (as a crash would) before it prints `READY`; it then returns as without one.
 */
object AbandonedRedisMain {
    @JvmStatic
    fun main(args: Array<String>) {
        if (args.firstOrNull() == "crashed") {
            val redis = EmbeddedRedis.start()
            val (pid, dir) = pidAndDir(redis.uri)
            redis.kill()
            println("READY $pid $dir")
            System.out.flush()
            readLine()
            return
        }
        val core = OptimusCore()
        val numbers = EventBlock<Int>()
        core.source("numbers", numbers)
        core.start()
        numbers.publish(1)
        val (pid, dir) = pidAndDir(core.redisUrl)
        println("READY $pid $dir")
        System.out.flush()
        if (args.firstOrNull() == "wait") {
            CountDownLatch(1).await() // the test's signal ends this JVM; its finally kills it at the latest
        } else {
            readLine()
        }
    }

    private fun pidAndDir(url: String): Pair<String, String> = Jedis(URI(url)).use { jedis ->
        val pid = Regex("process_id:(\\d+)").find(jedis.info("server"))!!.groupValues[1]
        pid to jedis.configGet("dir").getValue("dir")
    }
}

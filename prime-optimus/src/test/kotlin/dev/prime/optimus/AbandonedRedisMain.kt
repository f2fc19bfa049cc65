package dev.prime.optimus

import dev.prime.EventBlock
import redis.clients.jedis.Jedis
import java.net.URI

/**
 * Run by [EmbeddedRedisShutdownHookTest] in a JVM of its own: starts an [OptimusCore] on its
 * embedded Redis and never closes it. Prints `READY <redis pid> <redis working directory>`, then
 * returns from `main` when it reads a line from its standard input (or the input ends); the test
 * may signal it instead.
 */
object AbandonedRedisMain {
    @JvmStatic
    fun main(args: Array<String>) {
        val core = OptimusCore()
        val numbers = EventBlock<Int>()
        core.source("numbers", numbers)
        core.start()
        numbers.publish(1)
        val (pid, dir) = Jedis(URI(core.redisUrl)).use { jedis ->
            val pid = Regex("process_id:(\\d+)").find(jedis.info("server"))!!.groupValues[1]
            pid to jedis.configGet("dir").getValue("dir")
        }
        println("READY $pid $dir")
        System.out.flush()
        readLine()
    }
}

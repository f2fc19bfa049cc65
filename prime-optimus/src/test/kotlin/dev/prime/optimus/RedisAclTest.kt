package dev.prime.optimus

import dev.prime.EventBlock
import dev.prime.PrimeException
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import redis.clients.jedis.Jedis
import java.net.URI

/** A Redis user that lacks a command or key Optimus needs gets a message that names it and where the list is. */
class RedisAclTest {

    @Test
    fun aUserWithoutTheTopologysKeysIsToldWhichPatternToGrant() {
        val user = "prime-otherkeys"
        withUser(user, "~other:*", "&*", "+@all") { url ->
            OptimusCore.builder().redis(url).config(dev.prime.CoreConfig.builder().name("locked").build()).build().use { core ->
                val numbers = core.source("numbers", EventBlock<Int>())
                val refused = assertThrows(PrimeException::class.java) { numbers.reader() }
                val message = refused.message!!
                assertTrue("'$user'" in message, message)
                assertTrue("prime:{locked}:*" in message, message)
            }
        }
    }

    @Test
    fun deletingAClosedCoresKeysWithoutScanIsToldToGrantIt() {
        val user = "prime-noscan"
        withUser(user, "~*", "&*", "+@all", "-scan") { url ->
            val core = OptimusCore.builder().redis(url).config(dev.prime.CoreConfig.builder().name("noscan").build()).build()
            core.use { it.start() }
            val refused = assertThrows(PrimeException::class.java) { core.deleteKeys() }
            val message = refused.message!!
            assertTrue("delete the keys of topology 'noscan' was refused: the Redis user '$user' lacks the command 'scan'" in message, message)
            assertTrue("ACL SETUSER $user +scan" in message, message)
        }
    }

    @Test
    fun aUserWithoutACommandOptimusNeedsIsToldWhichOne() {
        val user = "prime-noscript"
        withUser(user, "~*", "&*", "+@all", "-evalsha", "-eval") { url ->
            OptimusCore.builder().redis(url).build().use { core ->
                val numbers = core.source("numbers", EventBlock<Int>())
                val refused = assertThrows(PrimeException::class.java) { numbers.reader() }
                val message = refused.message!!
                assertTrue("'$user'" in message, message)
                assertTrue("evalsha" in message.lowercase(), message)
                assertTrue("docs/architecture.md" in message, message)
            }
        }
    }

    @Test
    fun aCallerAndAReaderWithoutACommandTheyNeedAreToldWhichOne() {
        val user = "prime-noblmove"
        withUser(user, "~*", "&*", "+@all", "-blmove") { url ->
            val config = dev.prime.CoreConfig.builder().name("acl-caller").build()
            // hosts nothing: the call's request waits in Redis, and the caller's wait for the reply needs BLMOVE
            OptimusCore.builder().redis(url).config(config).hosts(emptyList()).callTimeout(java.time.Duration.ofSeconds(5)).build().use { core ->
                val twice = core.chain("twice") { x: Int -> 2 * x }.toBlock()
                val reader = core.source("numbers", EventBlock<Int>()).reader()
                core.start()
                for (refused in listOf(
                    assertThrows(PrimeException::class.java) { twice.process(1) },
                    assertThrows(PrimeException::class.java) { reader.take(java.time.Duration.ofSeconds(2)) },
                )) {
                    val message = refused.message!!
                    assertTrue("'$user'" in message, message)
                    assertTrue("'blmove'" in message.lowercase(), message)
                    assertTrue("docs/architecture.md" in message, message)
                }
            }
        }
    }

    /**
     * Runs [body] with the URL of a Redis user [user] (password `secret`) that has the ACL [rules]
     * besides `reset on`, deleting the user afterwards.
     */
    private fun withUser(user: String, vararg rules: String, body: (String) -> Unit) {
        Jedis(URI(TestRedis.url)).use { admin ->
            admin.sendCommand(redis.clients.jedis.Protocol.Command.ACL, "SETUSER", user, "reset", "on", ">secret", *rules)
        }
        try {
            body(TestRedis.url.replace("redis://", "redis://$user:secret@"))
        } finally {
            Jedis(URI(TestRedis.url)).use { admin -> admin.sendCommand(redis.clients.jedis.Protocol.Command.ACL, "DELUSER", user) }
        }
    }
}

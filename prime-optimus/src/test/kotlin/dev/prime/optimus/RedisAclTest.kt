package dev.prime.optimus

import dev.prime.EventBlock
import dev.prime.PrimeException
import dev.prime.conformance.CapturedStderr
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.params.ParameterizedTest
import org.junit.jupiter.params.provider.ValueSource
import redis.clients.jedis.Jedis
import java.net.URI
import java.nio.file.Files
import java.nio.file.Path

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

    @Test
    fun theDocumentedPermissionsAreAllRedisIsAskedFor() {
        // docs/architecture.md, "Redis permissions": the example's commands, for this test's key pattern
        val example = Files.readAllLines(Path.of("..", "docs", "architecture.md")).single { it.startsWith("ACL SETUSER robot ") }
        val commands = example.split(" ").filter { it.startsWith("+") }
        val user = "prime-documented"
        withUser(user, "~prime:{acl-documented}:*", *commands.toTypedArray()) { url ->
            Jedis(URI(TestRedis.url)).use { it.aclLogReset() }
            val config = dev.prime.CoreConfig.builder().name("acl-documented").build()
            OptimusCore.builder().redis(url).config(config).callTimeout(java.time.Duration.ofSeconds(10)).build().use { core ->
                val numbers = EventBlock<Int>()
                val reader = core.source("numbers", numbers).then(core.chain("inc") { x: Int -> x + 1 }).reader()
                val twice = core.chain("twice") { x: Int -> 2 * x }.toBlock() // only called: its lone requests take the cheaper step
                core.start()
                (1..5).forEach(numbers::publish)
                assertEquals((2..6).toList(), (1..5).map { reader.take(java.time.Duration.ofSeconds(10)).orElseThrow() })
                assertEquals((1..5).map { 2 * it }, (1..5).map { twice.process(it) })
            }
            val refused = Jedis(URI(TestRedis.url)).use { admin -> admin.aclLog().filter { it.username == user }.map { "${it.reason} ${it.`object`}" } }
            assertEquals(emptyList<String>(), refused, "what Redis refused the user with the documented permissions (ACL LOG)")
        }
    }

    /**
     * A service only called steps a lone request without the script ([RequestStep]) when its user
     * may send `multi`, `exec`, `watch` and `unwatch`. A user that lacks one gets one ERROR line
     * naming it, and the service steps its calls with the script: every call answered once, in
     * order, none lost or doubled.
     */
    @ParameterizedTest(name = "without {0}")
    @ValueSource(strings = ["multi", "exec", "watch", "unwatch"])
    fun aServiceOnlyCalledWhoseUserLacksACommandOfTheStepWithoutTheScriptSaysSoOnceAndGoesOn(command: String) {
        val example = Files.readAllLines(Path.of("..", "docs", "architecture.md")).single { it.startsWith("ACL SETUSER robot ") }
        val commands = example.split(" ").filter { it.startsWith("+") && it != "+$command" }
        val user = "prime-no$command"
        withUser(user, "~prime:{acl-no-$command}:*", *commands.toTypedArray()) { url ->
            val config = dev.prime.CoreConfig.builder().name("acl-no-$command").build()
            CapturedStderr().use { err ->
                OptimusCore.builder().redis(url).config(config).callTimeout(java.time.Duration.ofSeconds(10)).build().use { core ->
                    val twice = core.chain("twice") { x: Int -> 2 * x }.toBlock()
                    core.start()
                    assertEquals((1..30).map { 2 * it }, (1..30).map { twice.process(it) })
                }
                val errors = err.lines().filter { " ERROR " in it && "'$command'" in it }
                assertEquals(1, errors.size, "ERROR lines naming '$command': $errors")
                assertTrue("service 'twice'" in errors.single() && "'$user'" in errors.single(), errors.single())
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

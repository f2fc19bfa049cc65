package dev.prime.kotlin

import dev.prime.PrimeCore
import dev.prime.Source
import dev.prime.liberty.LibertyCore
import kotlinx.coroutines.flow.Flow
import org.junit.jupiter.api.Assertions.assertInstanceOf
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.assertThrows
import java.lang.reflect.InvocationTargetException
import java.lang.reflect.Method

/**
 * `SourceFlows.asFlow(source)`, `FlowSources.source(core, [name,] flow)`,
 * `SuspendingBlocks.suspendingBlock(context, logic)` and
 * `SuspendingBlocks.processSuspending(block, input, context, continuation)` called from Java (here
 * through the very methods Java links to) with a `null` refuse it with a [NullPointerException]
 * naming the parameter and saying what to pass, as the core's declarations do.
 */
class JavaNullArgumentsTest {

    @Test
    fun asFlowFromJavaNamesTheNullSource() {
        val method = javaMethod("dev.prime.kotlin.SourceFlows", "asFlow", Source::class.java)
        assertRefused(method, arrayOf(null), "source must not be null", "pass the Source")
    }

    @Test
    fun sourceOfAFlowFromJavaNamesTheNullArgument() {
        val unnamed = javaMethod("dev.prime.kotlin.FlowSources", "source", PrimeCore::class.java, Flow::class.java)
        val named = javaMethod("dev.prime.kotlin.FlowSources", "source", PrimeCore::class.java, String::class.java, Flow::class.java)
        LibertyCore().use { core ->
            assertRefused(unnamed, arrayOf(core, null), "flow must not be null", "pass the Flow")
            assertRefused(unnamed, arrayOf(null, emptyFlow()), "core must not be null", "pass the PrimeCore")
            assertRefused(named, arrayOf(core, "named", null), "flow must not be null", "pass the Flow")
            assertRefused(named, arrayOf(core, null, emptyFlow()), "name must not be null", "pass the source's name")
            assertRefused(named, arrayOf(null, "named", emptyFlow()), "core must not be null", "pass the PrimeCore")
        }
    }

    @Test
    fun suspendingBlockFromJavaNamesTheNullArgument() {
        val method = javaMethod(
            "dev.prime.kotlin.SuspendingBlocks", "suspendingBlock",
            kotlin.coroutines.CoroutineContext::class.java, kotlin.jvm.functions.Function2::class.java,
        )
        val logic: suspend (Int) -> Int = { it }
        assertRefused(method, arrayOf(kotlin.coroutines.EmptyCoroutineContext, null), "logic must not be null", "pass the suspending function")
        assertRefused(method, arrayOf(null, logic), "context must not be null", "EmptyCoroutineContext")
    }

    @Test
    fun processSuspendingFromJavaNamesTheNullArgument() {
        val method = javaMethod(
            "dev.prime.kotlin.SuspendingBlocks", "processSuspending",
            dev.prime.Block::class.java, Any::class.java,
            kotlin.coroutines.CoroutineContext::class.java, kotlin.coroutines.Continuation::class.java,
        )
        val block = dev.prime.Block<Int, Int> { it }
        val continuation = object : kotlin.coroutines.Continuation<Any?> {
            override val context: kotlin.coroutines.CoroutineContext = kotlin.coroutines.EmptyCoroutineContext
            override fun resumeWith(result: Result<Any?>) {}
        }
        assertRefused(method, arrayOf(null, 1, kotlinx.coroutines.Dispatchers.IO, continuation), "block must not be null", "pass the Block")
        assertRefused(method, arrayOf(block, 1, null, continuation), "context must not be null", "Dispatchers.IO")
    }

    private fun emptyFlow(): Flow<Int> = kotlinx.coroutines.flow.emptyFlow()

    private fun javaMethod(facade: String, name: String, vararg parameters: Class<*>): Method =
        Class.forName(facade).getMethod(name, *parameters)

    private fun assertRefused(method: Method, arguments: Array<Any?>, vararg parts: String) {
        val thrown = assertThrows<InvocationTargetException> { method.invoke(null, *arguments) }.targetException
        assertInstanceOf(NullPointerException::class.java, thrown)
        for (part in parts) assertTrue(thrown.message.orEmpty().contains(part), "'${thrown.message}' says '$part'")
    }
}

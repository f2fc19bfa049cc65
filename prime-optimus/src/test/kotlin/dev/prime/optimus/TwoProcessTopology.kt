package dev.prime.optimus

import dev.prime.Block
import dev.prime.EventBlock
import dev.prime.Source

/**
 * The topology [TwoProcessTest] and [RemoteWorkerMain] both declare, in this one order: a source
 * of numbers through the linked chains "double" and "inc", and a chain "square" called
 * synchronously. The worker process hosts [WORKER_SERVICES], the test's process the rest.
 */
internal object TwoProcessTopology {
    val WORKER_SERVICES = listOf("double", "square")
    val TEST_SERVICES = listOf("inc")

    class Declared(val output: Source<Int>, val square: Block<Int, Int>)

    /**
     * Declares the topology; "double" takes [doubleMillis] per value and "square" [squareMillis]
     * per call (a host busy in its block, not in Redis).
     */
    fun declare(core: OptimusCore, numbers: EventBlock<Int>, doubleMillis: Long = 0, squareMillis: Long = 0): Declared {
        val output = core.source("numbers", numbers)
            .then(
                core.chain("double") { x: Int ->
                    if (doubleMillis > 0) Thread.sleep(doubleMillis)
                    x * 2
                }.then(core.chain("inc") { x: Int -> x + 1 }),
            )
        val square = core.chain("square") { x: Int ->
            if (squareMillis > 0) Thread.sleep(squareMillis)
            x * x
        }.toBlock()
        return Declared(output, square)
    }
}

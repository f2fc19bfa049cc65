package dev.prime.optimus

import dev.prime.Block
import dev.prime.spi.AbstractChain

/** A service of a chain, before it is bound to what follows it. */
internal class StageSpec(val name: String, val logic: StageLogic)

/**
 * An Optimus chain: the services it is made of, in order. Linking two chains concatenates their
 * services (the first's output list becomes the second's input: no extra hop); the services are
 * bound and start when the chain is used ([toBlock] or a link to a source).
 */
internal class OptimusChain<I, O>(
    private val optimus: OptimusCore,
    name: String,
    val stages: List<StageSpec>,
) : AbstractChain<I, O>(optimus, name) {

    /** Marks the chain used by a link that takes its services rather than its block. */
    fun take(): List<StageSpec> {
        consume()
        return stages
    }

    override fun createBlock(): Block<I, O> = optimus.bindForCalls(name(), stages)

    /** A call already encodes its input and result: [dev.prime.CoreConfig.valueCopies] adds nothing. */
    override fun copiesValuesItself(): Boolean = true
}

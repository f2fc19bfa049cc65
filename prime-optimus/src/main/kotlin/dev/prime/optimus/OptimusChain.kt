package dev.prime.optimus

import dev.prime.Block
import dev.prime.spi.AbstractChain

/** A service of a chain, before it is bound to what follows it. */
internal class StageSpec(val name: String, val logic: StageLogic)

/** The services a chain is made of, in order: the form a link of the same core takes ([dev.prime.PrimeCore.part]). */
internal class Stages(val specs: List<StageSpec>)

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

    /** Its services: what a link of the same core joins instead of calling [toBlock]. */
    override fun compiledForm(): Any = Stages(stages)

    override fun createBlock(): Block<I, O> = optimus.bindForCalls(name(), stages)

    /** A call already encodes its input and result: [dev.prime.CoreConfig.valueCopies] adds nothing. */
    override fun copiesValuesItself(): Boolean = true
}

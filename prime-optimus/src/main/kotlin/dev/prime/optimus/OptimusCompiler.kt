package dev.prime.optimus

import dev.prime.Block
import dev.prime.EventBlock
import dev.prime.Source
import dev.prime.ChainCompiler
import dev.prime.NodeLogic
import dev.prime.ServiceGauges
import dev.prime.SourceCompiler
import dev.prime.topology.TopologyNode

/** A service of a chain, before it is bound to what follows it. */
internal class StageSpec(val name: String, val logic: StageLogic)

/** The services a chain is made of, in order: Optimus's compiled form of a chain. */
internal class Stages(val specs: List<StageSpec>)

/**
 * Compiles the topology model's chain nodes into services: a chain made of a block (and every
 * template, as the core's generic block) is one service running it; another core's chain is one
 * service named as its node (`hosted(name)`) running its block; a link concatenates its parts'
 * services (the first's output list becomes the second's input: no extra hop). The services are
 * bound, and start, when the chain is used ([toBlock], or a link to a source). Its services' queue
 * depths and dead letters are read from Redis for the core's metrics ([RedisServiceGauges]).
 */
internal class OptimusChainCompiler(private val core: OptimusCore) : ChainCompiler<Stages>, ServiceGauges {
    private val gauges = RedisServiceGauges(core)

    override fun queueDepth(service: String): Long = gauges.queueDepth(service)

    override fun hasQueue(service: String): Boolean = gauges.hasQueue(service)

    override fun deadLetters(service: String): Long = gauges.deadLetters(service)

    override fun missed(source: String): Long = gauges.missed(source)

    override fun form(): Class<Stages> = Stages::class.java

    override fun block(chain: String, block: Block<*, *>): Stages {
        core.declaredTypes.note(chain, block) // checked against the codec at start
        core.checkIsolatedUser(chain) // a user declared after start: its isolated chain's hosting
        return Stages(listOf(StageSpec(chain, core.chainLogic(block))))
    }

    override fun foreign(node: String, block: Block<*, *>): Stages = block(node, block)

    override fun template(node: TopologyNode, logic: NodeLogic, parts: List<Stages>): Stages? =
        if (node is TopologyNode.Link) Stages(parts[0].specs + parts[1].specs) else null

    /** A remote call to the chain's first service, its services bound now. */
    override fun toBlock(chain: String, form: Stages): Block<*, *> = core.bindForCalls<Any?, Any?>(chain, form.specs)

    /** The services [toBlock] bound for a part of a declaration that failed, stopped and forgotten. */
    override fun discard(chain: String, form: Stages): Boolean = core.unbindForCalls(chain)

    /** A call already encodes its input and result: [dev.prime.CoreConfig.valueCopies] adds nothing. */
    override fun copiesValues(): Boolean = true
}

/**
 * Compiles the topology model's source nodes into Redis: an event source is an [OptimusSource]
 * (a log list, reader lists and service queues), and a service of one (a linked chain's services,
 * a filter, a flat-map, a listener) reads its own queue of it.
 */
internal class OptimusSourceCompiler(private val core: OptimusCore) : SourceCompiler<OptimusSource<*>> {
    @Suppress("UNCHECKED_CAST")
    override fun form(): Class<OptimusSource<*>> = OptimusSource::class.java as Class<OptimusSource<*>>

    override fun <T> eventSource(name: String, events: EventBlock<T>): Source<T> = core.eventSource(name, events)

    @Suppress("UNCHECKED_CAST")
    override fun service(node: TopologyNode, logic: NodeLogic, input: OptimusSource<*>, chain: Any?): Source<*>? {
        val name = node.name()
        return when (node) {
            is TopologyNode.SourceLink -> core.serviceOn(input, (chain as Stages).specs, name, node.chain())
            is TopologyNode.Filter -> {
                val predicate = (logic as NodeLogic.Condition).condition() as java.util.function.Predicate<Any?>
                core.serviceOn(input, listOf(StageSpec(name, StageLogic { value, emit -> if (predicate.test(value)) emit(value) })), name)
            }
            is TopologyNode.FlatMap -> {
                val block = (logic as NodeLogic.Expand).block() as Block<Any?, Iterable<Any?>?>
                core.serviceOn(input, listOf(StageSpec(name, StageLogic { value, emit -> block.process(value)?.forEach(emit) })), name)
            }
            is TopologyNode.Listener -> {
                val listener = (logic as NodeLogic.Listen).listener() as java.util.function.Consumer<Any?>
                core.serviceOn(input, listOf(StageSpec(name, StageLogic { value, _ -> listener.accept(value) })), null)
            }
            else -> throw IllegalStateException("not a service of a source: $node")
        }
    }
}

package dev.prime.optimus

import dev.prime.PrimeCore
import dev.prime.Reader
import dev.prime.MediaSource

/**
 * A source kept in Redis: its newest values in a log list (for readers that come late), a set of
 * plain reader lists it publishes to (trimmed to the retention) and a set of service inputs it
 * publishes to (queues, never trimmed). Every process that declares the same topology has an equal
 * object for it; any of them can publish and read.
 */
internal class OptimusSource<T>(
    private val core: OptimusCore,
    private val name: String,
    /** Whether an [dev.prime.EventBlock] publishes to it (else a service does: [OptimusCore.publishAll] refuses it). */
    val ofEvents: Boolean,
) : MediaSource<T> {
    /**
     * Whether the event block that publishes to it is the program's (a source it declared), not
     * the core's own (a combinator's output, a timer): `null` until [OptimusCore.publishAll] first
     * looks it up in the topology.
     */
    @Volatile
    var programsEvents: Boolean? = null

    val keys = SourceKeys(
        name,
        core.keys.sourceLog(name),
        core.keys.sourceReaders(name),
        core.keys.sourceServices(name),
        core.config().sourceRetention(),
        core.keys.sourceSequence(name),
    )

    override fun core(): PrimeCore = core

    override fun name(): String = name

    override fun reader(): Reader<T> = core.newReader(this).also { core.recordReader(this) }

    override fun serviceReader(): Reader<T> = core.newReader(this)

    /** Itself: the form its core's services read it through ([OptimusSourceCompiler]). */
    override fun compiledForm(): Any = this

    override fun toString(): String = "OptimusSource[$name]"
}

package dev.prime.optimus

import dev.prime.EventBlock
import dev.prime.PrimeCore
import dev.prime.Reader
import dev.prime.Source

/**
 * The failover tests' topology on [core] (not started): a source `numbers`, published to with
 * `publishAll`, feeding a chain `double` that takes [serviceMillis] a value, slower than the
 * publisher, so values wait in Redis, in flight when a master is killed. Returns the source and a
 * reader of the doubled values.
 */
internal fun slowDoubling(core: PrimeCore, serviceMillis: Long): Pair<Source<Int>, Reader<Int>> {
    val source = core.source("numbers", EventBlock<Int>())
    val doubled = source.then(
        core.chain("double") { x: Int ->
            Thread.sleep(serviceMillis)
            x * 2
        },
    )
    return source to doubled.reader()
}

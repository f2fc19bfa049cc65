package dev.prime.optimus

/**
 * How the processes that host one service share it: set per service with
 * [OptimusCore.Builder.hosting]. Every process that hosts a service must declare the same mode for
 * it; a process that declares another is refused at `start()` (see [OptimusCore.Builder.hosting]).
 * Modes apply to the services of chains; combinators, timers and generic services are
 * [EXCLUSIVE] only.
 */
public enum class Hosting {
    /**
     * The default: one process hosts the service. A second process that names it in `hosts(...)`
     * waits up to one lease time at `start()` (a restarted worker takes over from a killed one),
     * then fails with an `IllegalStateException` ("already hosted by"): two hosts of such a
     * service are taken for a misconfiguration. Values leave the service in the order they came.
     */
    EXCLUSIVE,

    /**
     * One active host at a time, in order; other processes that host it are standbys: their
     * `start()` succeeds, and one of them takes over within about one lease time
     * ([OptimusCore.Builder.leaseTime]) after the active host dies, and within a third of it after
     * the active host closes. The new host first processes what the old one had taken and not
     * stored, then the input: values leave the service in the order they came, across failovers,
     * and none is lost or duplicated (results are stored in the step that acknowledges the input,
     * and only while the host lease is held). An active host that finds its lease taken (it was
     * frozen or cut off longer than the lease time) stops the service and stands by again; it
     * claims the lease again only once the stopped run has ended (a block still running returns
     * first), so one process never runs the service twice at once.
     */
    ORDERED,

    /**
     * Competing consumers: every process that hosts the service takes values from its input at
     * the same time, each into a processing list of its own, so a slow block scales with its hosts.
     * No order is kept between values (each host keeps its own). A host that dies loses nothing:
     * when its lease lapses, a surviving host moves what it had taken and not stored back to the
     * head of the input (a host that closes does so at once). A value's results are stored once
     * (only a host whose lease holds can store, and a reclaimed value was not stored); its block may
     * run again on another host if the first one died, froze or closed while in it (a closing host
     * gives back what it holds before its block returns). Duplicates that a producer
     * made (a publish retried after a lost reply) are skipped by value id downstream, within the
     * last 4,096 values a reader or single-hosted service saw, but may both be processed here.
     *
     * Not for a service that runs for an isolated chain (`core.isolate(chain)`: the chain's own
     * service, each chain of a linked chain, a template's parts, a repeater's chain): its hosts
     * would run the shared chain for two calls at once, which an isolated chain never does.
     * `start()` refuses it with an `IllegalArgumentException` naming the service and the isolated
     * chain (a user made after the start is refused at once); give such a service [EXCLUSIVE] or
     * [ORDERED]. With those, a process runs it once at a time; only a host frozen or cut off longer
     * than the lease may still be in a block when its successor takes over (its results are not
     * stored). The users of an isolated chain may be unordered.
     */
    UNORDERED,
}

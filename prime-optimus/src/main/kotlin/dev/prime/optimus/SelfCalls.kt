package dev.prime.optimus

/**
 * The thread that runs a request's block in service [name] in this process now, or `null`; one
 * per service name ([OptimusCore.serviceThread]), so every run of the service (a new seat of an
 * unordered one too) writes the same holder.
 *
 * A plain field, written only by that thread, around the block: a thread reads its own last write
 * here or another thread's, never a stale write of its own, so only a thread that runs the
 * service's block now sees itself ([SelfCalls]).
 */
internal class ServiceThread(val name: String) {
    @JvmField
    var running: Thread? = null
}

/**
 * Refuses a call to a user of isolated chain [shared] made from inside that chain: on the thread
 * that runs, in this process, one of the services that run only for it ([services]: its own, each
 * chain of a linked chain, and those of the chains it consumed and calls, such as a template's
 * parts or a repeater's chain). That call would wait for itself: the user's service waits for the
 * isolated chain, whose call is the one making it (and each service takes one request at a time).
 * A remote call to such a user holds one ([RemoteCall.selfCalls]); other calls hold none, so
 * their check is a read of a `null` field.
 *
 * What it cannot see: a call made on a thread that does not run one of those services, though on
 * the chain's behalf (the service of a chain its block calls through a block it was given, not
 * one it consumed; a thread the block hands the call to). Such a call waits as any call for a
 * busy isolated chain, up to the call timeout.
 */
internal class SelfCalls(private val shared: String, private val services: List<ServiceThread>) {
    /** Throws [IllegalStateException] if this thread runs a block for the isolated chain now. */
    fun check(chainName: String) {
        val current = Thread.currentThread()
        for (service in services) {
            if (service.running === current) {
                throw IllegalStateException(
                    "isolated chain '$shared' was called from inside itself: the block of service " +
                        "'${service.name}', which runs for it, called '$chainName', a user of the same isolated chain, " +
                        "on the thread that runs it, and the call would wait for itself. Inside the shared chain, " +
                        "call what it needs directly, not through a user of its own isolated chain",
                )
            }
        }
    }
}

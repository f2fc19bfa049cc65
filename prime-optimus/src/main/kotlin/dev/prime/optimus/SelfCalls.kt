package dev.prime.optimus

/**
 * Refuses a call to a user of isolated chain [shared] made from inside that chain: on a thread
 * that runs, in this process, a request's block of one of the services that run only for it
 * ([services]: its own, each chain of a linked chain, and those of the chains it consumed and
 * calls, such as a template's parts or a repeater's chain). That call would wait for itself: the
 * user's service waits for the isolated chain, whose call is the one making it (and each service
 * takes one request at a time). A remote call to such a user holds one
 * ([RemoteCall.selfCalls]); other calls hold none, so their check is a read of a `null` field.
 *
 * The thread's own record of the request it runs ([OptimusCore.runningRequest], which a service
 * sets around each request's block) says which service's block runs on it. The services in
 * [services] are never hosted unordered (`start()` refuses it), so a process runs each of them
 * once at a time.
 *
 * What it cannot see: a call made on a thread that does not run one of those services, though on
 * the chain's behalf (the service of a chain its block calls through a block it was given, not
 * one it consumed; a thread the block hands the call to). Such a call waits as any call for a
 * busy isolated chain, up to the call timeout.
 */
internal class SelfCalls(private val core: OptimusCore, private val shared: String, private val services: Set<String>) {
    /** Throws [IllegalStateException] if this thread runs a block for the isolated chain now. */
    fun check(chainName: String) {
        val running = core.runningRequest()
        val service = running.service
        if (running.active && service in services) {
            throw IllegalStateException(
                "isolated chain '$shared' was called from inside itself: the block of service " +
                    "'$service', which runs for it, called '$chainName', a user of the same isolated chain, " +
                    "on the thread that runs it, and the call would wait for itself. Inside the shared chain, " +
                    "call what it needs directly, not through a user of its own isolated chain",
            )
        }
    }
}

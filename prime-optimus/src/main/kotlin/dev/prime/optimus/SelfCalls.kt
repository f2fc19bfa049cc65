package dev.prime.optimus

import java.util.concurrent.ConcurrentHashMap

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
 * A call made on a thread that runs none of those services, for a call that one of them waits
 * for in this process (the service of a chain its block calls through a block it was given, not
 * one it consumed), is seen through the services waiting on the way of calls ([CallPaths]). What
 * it cannot see: a call made on a thread the block hands it to, or in another process. Such a
 * call waits as any call for a busy isolated chain, up to the call timeout.
 */
internal class SelfCalls(private val core: OptimusCore, private val shared: String, private val services: Set<String>) {
    /** Each of [services] by the name a [CallPaths] path gives it. */
    private val serviceKeys: Map<String, String> = services.associateWith { CallPaths.named(core.keys.serviceInput(it)) }

    /**
     * Throws [IllegalStateException] if this thread runs a block for the isolated chain now, or
     * for a call that such a block waits for in this process ([CallPaths]).
     */
    fun check(chainName: String) {
        checkThisThread(chainName)
        val path = CallPaths.current() ?: return
        val waiting = serviceKeys.entries.firstOrNull { path.waits(it.value) } ?: return
        throw IllegalStateException(
            "isolated chain '$shared' was called from inside itself: its service '${waiting.key}', which runs for it, " +
                "is waiting for the call that led to this one (through a chain its block called), and '$chainName' is a " +
                "user of the same isolated chain, so the call would wait for itself. Inside the shared chain, call what " +
                "it needs directly, not through a user of its own isolated chain",
        )
    }

    private fun checkThisThread(chainName: String) {
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

/**
 * The services of this process that wait, on the way of calls, for what the current thread does:
 * seen by a call made on a service's thread that goes to one of them, which would wait for itself
 * ([OptimusCore.refuseCallOnItsOwnPath]), wherever in the path that service is.
 *
 * A service names itself and the services that wait for the request it takes around the request's
 * block ([entered]); a call made in that block records the path for its request id while it
 * waits ([waitingFor]), each service with the id of the call it waits for, so a service whose
 * call gave up (its call timeout) is no longer taken for waiting ([CallPath.waits]), so the service that takes the request in this process (of any core of
 * the JVM: a core of the same topology shares its services) adds it to its own. So a chain called
 * back by a chain its block calls, a template called by its part, and a chain called through the
 * block of another core of the same topology in this process are seen, not only the call made on
 * the thread of the very service it goes to ([OptimusCore.refuseCallThroughItself]).
 *
 * A service is named by its input list's key ([Keys.serviceInput]), which holds its topology's
 * name: services of two topologies are never taken for each other. The path does not travel with
 * a request to another process: a call back made there waits as any call for a busy service, until
 * the call timeout, as does one made on a thread the block hands it to. A call made on a thread
 * that runs no request (a user's, a value's service) starts no path and costs a thread-local
 * read; a request a service takes costs a read of whether any call waits in this process.
 */
internal object CallPaths {
    /** The path of the request the current thread runs a block for; `null` on a thread that runs none. */
    private val current = ThreadLocal<CallPath?>()

    /**
     * The callers of each call made, in this process, from a request's block, by its request id,
     * while it waits: each service on the path, with the id of the call it waits for.
     */
    private val waiting = ConcurrentHashMap<Long, Map<String, Long>>()

    /** The path of the request the current thread runs a block for, or `null`. */
    fun current(): CallPath? = current.get()

    /**
     * A service ([self]: its path alone, [CallPath.alone]) takes request [id]: its path is [self]
     * and the callers of the call that made the request, if made in this process and still waiting.
     */
    fun entered(id: Long, self: CallPath) {
        val callers = if (waiting.isEmpty()) null else waiting[id]
        current.set(if (callers == null) self else CallPath(self.self, callers))
    }

    /** The service's block for the request has returned. */
    fun left() = current.set(null)

    /** Runs [call], the call of request [id] made with [path] (see [current]; `null`: none), recording the path meanwhile. */
    inline fun <T> waitingFor(id: Long, path: CallPath?, call: () -> T): T {
        if (path == null) return call()
        record(id, path)
        try {
            return call()
        } finally {
            forget(id)
        }
    }

    fun record(id: Long, path: CallPath) {
        waiting[id] = path.callersOf(id)
    }

    fun forget(id: Long) {
        waiting.remove(id)
    }

    /** Whether the call of request [id] made in this process still waits for its reply. */
    fun stillWaiting(id: Long): Boolean = waiting.containsKey(id)

    /** The text of service key [key], as paths hold it. */
    fun named(key: ByteArray): String = String(key, Charsets.ISO_8859_1)
}

/**
 * The services that wait for what a thread does ([CallPaths]): [self], the service whose block it
 * runs, and [callers], each service that waits, on the way of calls, for the request it runs,
 * with the id of the call that service's block made. A caller whose call gave up (its call
 * timeout, an interrupt) is free again: it no longer waits, though the request it made still
 * runs, so a call back to it is not refused.
 */
internal class CallPath(val self: String, private val callers: Map<String, Long>) {
    /** Whether service [key] waits for what this thread does: it runs its block, or its call on the way still waits. */
    fun waits(key: String): Boolean {
        if (key == self) return true
        val id = callers[key] ?: return false
        return CallPaths.stillWaiting(id)
    }

    /** The callers of call [id] made by this thread's block: [callers] and [self], which waits for it. */
    fun callersOf(id: Long): Map<String, Long> = if (callers.isEmpty()) mapOf(self to id) else callers + (self to id)

    companion object {
        /** The path of service [key] that runs a request no call of this process waits for. */
        fun alone(key: String): CallPath = CallPath(key, emptyMap())
    }
}

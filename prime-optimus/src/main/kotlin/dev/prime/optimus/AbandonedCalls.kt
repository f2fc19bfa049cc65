package dev.prime.optimus

/**
 * Calls whose caller gave up (an interrupt, its timeout) after a service had taken the request.
 *
 * Design note. A caller that gives up takes its request back from the service's input list; a
 * request a service already took cannot be taken back, and a block usually runs at once, so its
 * late reply is merely skipped. A block that waits for an isolated chain ([dev.prime.PrimeCore.isolate])
 * may wait long, though, and should not then run for nobody: so when nothing was left to take
 * back, [WITHDRAW] marks the request's id as abandoned, in the same atomic script. The service
 * thread that runs the request looks for the mark ([OptimusCore.callerGaveUp]) only while the
 * block waits for its turn and once when the turn comes after a wait, never on a call's fast
 * path. A mark expires after [MARK_MILLIS]; marks are made only for requests a service holds,
 * at most one per waiting service thread and give-up, so they stay few. The script is sent as
 * text ([Script.runText]), so a withdrawal is one round trip, within its bound, even on a Redis
 * that does not know the script yet.
 */
internal object AbandonedCalls {
    /** How long a mark lives: longer than any sensible wait for an isolated chain. */
    const val MARK_MILLIS: Long = 3_600_000L

    /**
     * KEYS: 1 the input list of the service the request went to, 2 the request's abandoned mark
     * ([Keys.abandonedCall]). ARGV: 1 the request entry, 2 [MARK_MILLIS]. Removes every copy of
     * the request (a retry may have pushed two); if there was none, a service took it: marks it.
     * Returns how many copies it removed.
     */
    val WITHDRAW: Script = Script(
        """
        local removed = redis.call('LREM', KEYS[1], 0, ARGV[1])
        if removed == 0 then redis.call('SET', KEYS[2], '1', 'PX', ARGV[2]) end
        return removed
        """,
    )
}

/** The request a service thread runs a block for, if [active] ([OptimusCore.runningRequest]); one per thread, reused. */
internal class RunningRequest {
    /** The request's id (meaningful while [active]). */
    var id: Long = 0L

    /** The service whose block runs for the request (meaningful while [active]; see [SelfCalls]). */
    var service: String? = null

    /** Whether the thread runs a request's block now. */
    var active: Boolean = false
}

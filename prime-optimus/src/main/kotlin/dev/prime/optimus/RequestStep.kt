package dev.prime.optimus

import redis.clients.jedis.CommandArguments
import redis.clients.jedis.Connection
import redis.clients.jedis.Jedis
import redis.clients.jedis.Protocol
import redis.clients.jedis.exceptions.JedisConnectionException
import redis.clients.jedis.exceptions.JedisDataException
import redis.clients.jedis.exceptions.JedisNoScriptException
import java.nio.charset.StandardCharsets.UTF_8

/**
 * The one entry a step of a service only called stores for a lone request: the caller's reply
 * ([isReply], pushed to the reply list [target]) or, in a chain, the request forwarded to the next
 * service's input [target].
 */
internal class RequestOutput(val target: ByteArray, val entry: ByteArray, val isReply: Boolean)

/**
 * The step of a service only called (no source feeds it, so its input holds requests and keeps
 * no queue count) that handled one request into one [RequestOutput]: the call's hot path, run as
 * [Script.REQUEST_STEP] instead of the general [Script.STEP]. It keeps every promise of the general
 * step that applies to such a step, in the same order and atomically: the host-lease fence, the
 * reply namespace check and expiry, the acknowledgement of the request, and the take of the next
 * entries under the same bounds; what it cannot store itself (a reply key it refuses) it leaves
 * untouched, and the caller then runs the general step, which dead-letters the request.
 *
 * [executeThenWait] writes the service's next blocking take (`BLMOVE input processing`) behind
 * the step, in the same write, as a raw echo's pop follows its push: a service that is keeping up
 * costs Redis one read per request, not two. The step then leaves one entry of a backlog in the
 * input for that take, so the take never waits while the service holds entries to handle. What the
 * take moved is in the processing list behind what the step took, as a crash would leave it.
 *
 * Design note: the step without a script ([storeWatched]). Every blocking take this class writes
 * is followed, in the same write, by `WATCH lease processing`, `GET lease`, `LLEN processing` and
 * `LLEN input`; Redis runs them when the take ends, so their answers come with the taken entry. If
 * the lease held this instance's id, the processing list held just the taken entry and the input
 * was empty (a service that keeps up, the call path), the step of that entry can be a transaction
 * of plain commands: `MULTI`, `LMOVE processing target` (the acknowledgement: it fails, moving
 * nothing, when the target is not a list), `LSET target -1 entry` (the moved request becomes the
 * result), `PEXPIRE` for a reply, `EXEC`. Redis refuses the `EXEC` if the lease or the processing
 * list was touched or expired after the `WATCH`: lost to another instance, lapsed, or renewed by
 * this instance's heartbeat. So a host that lost its lease stores nothing, as with the script; a
 * step refused for any reason (the lease, a target of the wrong type) is stored by the general
 * step instead, which answers the fence and dead-letters as usual. The transaction costs Redis
 * about a third of the script's time (no Lua). It must run on the very connection that sent the
 * `WATCH` (a new connection has none and would run unfenced): [storeWatched] checks the
 * connection it is given, and a connection closed meanwhile is never opened again ([OneSocket]),
 * so what was written to it before it closed is discarded with it by Redis. A target of the wrong
 * type gets the reply expiry (`PEXPIRE` cannot be made to depend on the `LMOVE`); its value is
 * left as it was.
 */
internal class RequestStep(
    private val processing: ByteArray,
    private val input: ByteArray,
    private val fence: HostFence,
    private val rules: StepRules,
) {
    private val batchBytes = number(rules.batchBytes)
    private val maxEntryBytes = number(rules.maxEntryBytes)
    private val replyTtl = number(rules.replyTtlMillis)

    /**
     * Stores [output], acknowledges the request (the head of the processing list) and takes up to
     * [take] entries. Returns [StepResult.Stored], [StepResult.Fenced] or (when it takes)
     * [StepResult.Stray], or `null` if the script refused the reply key and stored nothing (run the
     * general step for this request).
     */
    fun execute(jedis: Jedis, output: RequestOutput, take: Int): StepResult? =
        parse(Script.REQUEST_STEP.run(jedis, keys(output), args(output, take, waitBehind = false)))

    /**
     * [execute] with a full take, then the blocking take of the next entry (waiting up to
     * [waitSeconds]), in one write; the step's result as [execute]'s, a stored step's taken
     * entries followed by the one the blocking take moved, if it moved one.
     * A step Redis refused throws its error once both answers are read (what the blocking take
     * moved is then in the processing list, for the service to read there); a blocking take Redis
     * refused counts as one that moved nothing.
     */
    fun executeThenWait(jedis: Jedis, output: RequestOutput, take: Int, waitSeconds: ByteArray): StepResult? {
        forget()
        val connection = jedis.connection
        Script.REQUEST_STEP.send(connection, keys(output), args(output, take, waitBehind = true))
        sendTake(connection, waitSeconds, unwatch = true)
        val step = connection.getMany(1)[0]
        val result = when (step) {
            // Redis lost its scripts (a restart): nothing was stored; the request is still the processing list's head
            is JedisNoScriptException -> {
                readTake(jedis, unwatch = true) // the take was written behind the step: its answers come first
                return execute(jedis, output, take = 0)
            }
            is RuntimeException -> {
                readTake(jedis, unwatch = true)
                throw step
            }
            else -> parse(step)
        }
        // a blocking take Redis refused moved nothing (never thrown here: the step may be stored); the next take meets it again
        val moved = readTake(jedis, unwatch = true, guarded = result is StepResult.Stored && result.taken.isEmpty())
            ?.let { TakenEntry(it, it.size.toLong()) }
        return if (result is StepResult.Stored && moved != null) StepResult.Stored(result.taken + moved, result.missed, result.view) else result
    }

    /**
     * Whether steps may go without the script: only once [checkPermissions] found that the Redis
     * user may send all it needs. Until then, and for good after a refusal, takes are not watched
     * and every step goes with the script.
     */
    private var withoutScript = false

    /** Whether [checkPermissions] has run to its end. */
    var permissionsChecked: Boolean = false
        private set

    /**
     * Checks that the Redis user may send what a step without the script adds to the script's
     * commands (`watch`, `unwatch`, `multi`, `exec`): sends them with nothing to guard or run
     * (`WATCH lease`, `UNWATCH`, `MULTI`, `EXEC`). Returns the first refusal, after which steps go
     * with the script for good, or `null`, after which they may go without it. Without this check
     * a user lacking `multi` would have the transaction's commands run one by one, unguarded.
     * After a refusal the connection may be left watching or inside a transaction: drop it.
     */
    fun checkPermissions(jedis: Jedis): JedisDataException? {
        forget()
        val connection = jedis.connection
        connection.sendCommand(commandOf(Protocol.Command.WATCH, fence.lease))
        connection.sendCommand(UNWATCH)
        connection.sendCommand(MULTI)
        connection.sendCommand(EXEC)
        val refusal = connection.getMany(4).firstOrNull { it is JedisDataException && RedisPermissions.isRefusal(it) }
        withoutScript = refusal == null
        permissionsChecked = true
        return refusal as JedisDataException?
    }

    /**
     * The blocking take of an idle service (`BLMOVE input processing`, waiting up to [waitSeconds]),
     * watched so that the step of what it moves may go without the script ([storeWatched]); the
     * moved entry, or `null`. A take Redis refused throws its error.
     */
    fun takeWatched(jedis: Jedis, waitSeconds: ByteArray): ByteArray? {
        forget()
        sendTake(jedis.connection, waitSeconds, unwatch = true)
        return readTake(jedis, unwatch = true, guarded = true, throwRefusal = true)
    }

    /** Whether the step of [entry], just taken on [jedis], may be stored by [storeWatched]. */
    fun isWatched(jedis: Jedis, entry: ByteArray): Boolean = jedis === watchedOn && entry === watchedEntry

    /**
     * Stores [output] of the entry the last take on [jedis] moved, by a transaction the `WATCH` of
     * that take guards (see the design note), then writes the next blocking take behind it; returns
     * whether the transaction stored it (`false`: Redis refused it, nothing was stored, and the
     * request is still the processing list's head: store it with the general step). Either way,
     * read the take's answers next with [readTakeBehind] on the same connection.
     *
     * @throws IllegalStateException if the entry's take was not watched on this connection
     */
    fun storeWatched(jedis: Jedis, output: RequestOutput, waitSeconds: ByteArray): Boolean {
        check(jedis === watchedOn) { "the step of a request without the script needs the WATCH of its take on the same connection" }
        forget()
        val connection = jedis.connection
        // a closed connection has lost the WATCH: it fails here, or at the first command written after it closed ([OneSocket])
        if (!connection.isConnected || connection.isBroken) throw JedisConnectionException("the connection that watched the take is closed")
        connection.sendCommand(MULTI)
        connection.sendCommand(commandOf(Protocol.Command.LMOVE, processing, output.target, LEFT, RIGHT))
        connection.sendCommand(commandOf(Protocol.Command.LSET, output.target, LAST, output.entry))
        if (output.isReply) connection.sendCommand(commandOf(Protocol.Command.PEXPIRE, output.target, replyTtl))
        connection.sendCommand(EXEC)
        sendTake(connection, waitSeconds, unwatch = false) // EXEC ended every WATCH
        val answers = connection.getMany(if (output.isReply) 5 else 4)
        val exec = answers.last() as? List<*> ?: return false // refused: a WATCHed key changed, or a command was refused at queueing
        return exec.none { it is Exception } && exec[0] != null
    }

    /** The take [storeWatched] wrote behind its transaction: the moved entry, or `null` (moved nothing, or Redis refused it). */
    fun readTakeBehind(jedis: Jedis): ByteArray? = readTake(jedis, unwatch = false, guarded = true)

    /** The connection whose `WATCH` guards the step of [watchedEntry], the entry its last take moved. */
    private var watchedOn: Jedis? = null
    private var watchedEntry: ByteArray? = null

    private fun forget() {
        watchedOn = null
        watchedEntry = null
    }

    private fun sendTake(connection: Connection, waitSeconds: ByteArray, unwatch: Boolean) {
        val take = if (waitSeconds === takeWait) {
            takeCommand
        } else {
            commandOf(Protocol.Command.BLMOVE, input, processing, LEFT, RIGHT, waitSeconds)
        }
        connection.sendCommand(take)
        if (!withoutScript) return
        // answered when the take ends: an earlier WATCH left on the connection could only make a later EXEC refuse
        if (unwatch) connection.sendCommand(UNWATCH)
        for (command in watchGroup) connection.sendCommand(command)
    }

    /** The commands every take writes (built once: nothing of them is allocated per request). */
    private var takeWait: ByteArray? = null
    private var takeCommand: CommandArguments = commandOf(Protocol.Command.BLMOVE)
    private val watchGroup = listOf(
        commandOf(Protocol.Command.WATCH, fence.lease, processing),
        commandOf(Protocol.Command.GET, fence.lease),
        commandOf(Protocol.Command.LLEN, processing),
        commandOf(Protocol.Command.LLEN, input),
    )

    /** Builds the take command for [waitSeconds] once, for a service that always waits as long. */
    fun waitingUpTo(waitSeconds: ByteArray): RequestStep {
        takeWait = waitSeconds
        takeCommand = commandOf(Protocol.Command.BLMOVE, input, processing, LEFT, RIGHT, waitSeconds)
        return this
    }

    /**
     * Reads what [sendTake] wrote: the moved entry (`null` if none, or if Redis refused the take,
     * unless [throwRefusal]). Watches the entry's step when the take is [guarded] (the processing
     * list held nothing else to store first), the lease held this instance's id, the entry is alone
     * in the processing list and the input is empty.
     */
    private fun readTake(jedis: Jedis, unwatch: Boolean, guarded: Boolean = false, throwRefusal: Boolean = false): ByteArray? {
        val answers = jedis.connection.getMany(if (!withoutScript) 1 else if (unwatch) 6 else 5)
        val taken = answers[0]
        if (throwRefusal && taken is RuntimeException) throw taken
        val moved = taken as? ByteArray ?: return null
        if (!withoutScript) return moved
        val at = if (unwatch) 2 else 1
        val holder = answers[at + 1]
        if (guarded && holder is ByteArray && holder.contentEquals(fence.instance) && answers[at + 2] == 1L && answers[at + 3] == 0L) {
            watchedOn = jedis
            watchedEntry = moved
        }
        return moved
    }

    private fun keys(output: RequestOutput) = listOf(processing, input, fence.lease, output.target)

    private fun args(output: RequestOutput, take: Int, waitBehind: Boolean) = listOf(
        fence.instance,
        output.entry,
        if (output.isReply) ONE else ZERO,
        rules.replyPrefix,
        replyTtl,
        number(take),
        batchBytes,
        maxEntryBytes,
        if (waitBehind) ONE else ZERO,
    )

    private fun parse(answer: Any?): StepResult? {
        val items = answer as List<*>
        return when (val status = (items[0] as ByteArray).toString(UTF_8)) {
            "OK" -> StepResult.Stored(
                if (items.size == 1) emptyList() else items.subList(1, items.size).map(::takenEntry),
                emptyList(),
                SourceView.NONE,
            )
            "FENCED" -> StepResult.Fenced((items[1] as ByteArray).toString(UTF_8))
            "STRAY" -> StepResult.Stray
            "REFUSED" -> null
            else -> throw IllegalStateException("unexpected answer of the request step script: $status")
        }
    }

    private companion object {
        val ONE = "1".toByteArray(UTF_8)
        val ZERO = "0".toByteArray(UTF_8)
        val LAST = "-1".toByteArray(UTF_8)
        val UNWATCH = commandOf(Protocol.Command.UNWATCH)

        fun number(n: Number): ByteArray = n.toString().toByteArray(UTF_8)

        /** An entry as the script returns it: whole, or `{size, prefix}` above the largest entry size. */
        fun takenEntry(item: Any?): TakenEntry =
            if (item is ByteArray) TakenEntry(item, item.size.toLong())
            else (item as List<*>).let { TakenEntry(it[1] as ByteArray, it[0] as Long) }
    }
}

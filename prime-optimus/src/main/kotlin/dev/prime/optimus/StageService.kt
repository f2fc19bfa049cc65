package dev.prime.optimus

import dev.prime.ChainFailedException
import dev.prime.CoreClosedException
import dev.prime.PrimeException
import dev.prime.internal.RateLimitedLog
import dev.prime.internal.ServiceThreads
import kotlinx.coroutines.CancellationException
import kotlinx.coroutines.currentCoroutineContext
import kotlinx.coroutines.delay
import kotlinx.coroutines.ensureActive
import org.slf4j.LoggerFactory
import redis.clients.jedis.args.ListDirection
import redis.clients.jedis.exceptions.JedisDataException
import java.nio.charset.StandardCharsets.UTF_8
import java.util.function.BooleanSupplier

/** What a service does with one input: emit any number of outputs (a chain emits exactly one). */
internal fun interface StageLogic {
    fun process(input: Any?, emit: (Any?) -> Unit)
}

/**
 * One Optimus service: a coroutine that moves values from its input list into its processing
 * list, processes them, and in one atomic [Script.STEP] stores the results (the next service's
 * input, a reply, a source, dead letters), acknowledges the inputs and takes the next ones.
 *
 * Design note. Jedis is blocking, so the coroutine runs on the core's own elastic thread pool
 * and blocks there; a blocking take asks Redis for at most one second, and closing the core
 * closes the connection, which wakes it at once. A value is removed from the processing list only
 * in the step that stores its results, so a crash of the process or of Redis (with persistence)
 * loses nothing: on start and after every reconnection the service first processes what its
 * processing list holds. Values seen recently (by id) are acknowledged without processing them
 * again, which absorbs duplicates from a producer that retried a push. A step that takes also
 * checks that the processing list holds just the entries it acknowledges: an entry an earlier
 * host's blocking take moved there after the host lease changed hands makes it store nothing and
 * read the list again ([StepResult.Stray]), so that entry is handled, not acknowledged unread.
 * A step that finds the host lease held by nobody stores nothing either: the batch may be stale
 * (another host may have held the lease meanwhile), so the service reads the list again, and its
 * read ([Script.PEEK]) is what re-claims the lease ([leaseLapsed]).
 *
 * Nothing an entry or a block does stops the service: every throwable but a
 * [VirtualMachineError] is caught on every path (a value's goes to the error handler and the
 * dead letters, a request's to its caller); an entry above the size limit is dead-lettered with
 * its first KiB; a step Redis refuses for a reason other than the connection (WRONGTYPE, OOM, a
 * script error) is stored again one entry at a time, and an entry Redis still refuses is
 * dead-lettered with Redis' answer. Connection failures, a Redis out of memory and a missing
 * permission are waited out as an outage (nothing could be stored, not even a dead letter). When the
 * queue this service feeds is full, the service holds its results and waits for room: an
 * internal hop never drops a value (the wait shows at the publisher as [QueueFullException]).
 *
 * Where it keeps what it took is its [HostSeat]: the service's own processing list, fenced by its
 * host lease (one host at a time), or, for a host of an [Hosting.UNORDERED] service, a list and a
 * lease of this host's own, with steps sized to about 5 ms of its block's work so that hosts share
 * the input ([HostSeat.nextTake]). A new run of an unordered service gets a new seat ([seatedAt]).
 *
 * A service only called (not [counted]) stores a lone request's step without the script when
 * its take was watched ([RequestStep.storeWatched]); a step Redis refuses there is stored at once
 * by the general step on a second connection ([refusedSteps]), since the first one is then
 * blocked in the take written behind the step.
 *
 * Memory: one batch of at most [BATCH] values and [StepRules.batchBytes] bytes (one entry may be
 * bigger, up to the entry size limit), and the last 4096 ids.
 */
internal class StageService(
    val name: String,
    private val core: OptimusCore,
    private val logic: StageLogic,
    /** The input list of the next service of the chain, or `null` if this one is the last. */
    private val next: ByteArray?,
    /** Where the last service of a chain linked to a source publishes. */
    private val output: SourceKeys?,
    /** Whether values reach this service's input (it is fed by a source), so its queue count is kept; else only calls do. */
    val counted: Boolean,
    /** Where this run keeps what it took: `null` for the service's own processing list (one host at a time). */
    seat: HostSeat? = null,
) {
    val input: ByteArray = core.keys.serviceInput(name)
    /** This service alone, as a [CallPaths] path names it. */
    private val onPath: CallPath = CallPath.alone(CallPaths.named(input))
    private val seat: HostSeat = seat ?: core.soleSeat(name)
    private val processing = this.seat.processing
    private val queued = core.keys.queuedOf(input)
    private val fence = this.seat.fence
    private val empty = StepBatch(
        processing, input, output, core.keys.deadLetters(name), core.keys.deadLettersTrimmed(name), next, core.stepRules,
        fence, counted,
    )
    private val rules = core.stepRules
    /** The cheaper step of a lone request, for a service only called (see [RequestStep]). */
    private val requestStep = if (counted) null else RequestStep(processing, input, fence, rules)

    private val idleWaitMillis = (this.seat.idleWaitSeconds * 1000).toLong()
    private val idleWaitArgument = this.seat.idleWaitSeconds.toString().toByteArray(UTF_8).also { requestStep?.waitingUpTo(it) }

    /**
     * Whether the last request step on this connection stored its request: only then is the next
     * blocking take written behind a request step. A step the script could not store (its script
     * not loaded after a Redis restart, a lease lapsed) would otherwise be answered only once that
     * take ended, up to a poll slice later.
     */
    private var waitBehindStep = false
    private val recent = RecentIds()

    /** The ids of the step being handled, to skip a value delivered twice within it; cleared for every step. */
    private val stepIds = RecentIds(Int.MAX_VALUE)
    private val deadLetterLog = RateLimitedLog(StageService::class.java.name) // one key: this service

    /** The reply owed to a caller whose request's block threw a [VirtualMachineError] (see [loop]). */
    private var fatalReply: Pair<ByteArray, ByteArray>? = null

    /** This service as one run of a host of a shared ([Hosting.UNORDERED]) service, in [seat]. */
    fun seatedAt(seat: HostSeat): StageService = StageService(name, core, logic, next, output, counted, seat)

    /** Where a refused transaction's request is stored at once (see [storeWatched]); connects when first used. */
    private val refusedSteps = RedisSession(core.connections)

    /** The codec's session this service decodes its inputs and encodes its outputs with, for its whole run. */
    private val held = core.holdCodec()

    /** The session of this run's loop while it runs: what [wake] closes the connection of. */
    @Volatile private var running: RedisSession? = null

    suspend fun run() {
        try {
            RedisSession(core.connections).use { session ->
                running = session
                loop(session)
            }
        } finally {
            running = null
            held?.close()
            refusedSteps.close()
            deadLetterLog.flush() // the dead letters counted since the last line
        }
    }

    /**
     * Wakes this run, just cancelled, from a blocking take: a cancellation does not end a Jedis
     * call, which would end only when the take's wait in Redis is over (up to a second, or a
     * third of the lease); closing the connection under it ends it at once, and the run then ends.
     * What it took stays in its processing list, as after a broken connection.
     */
    fun wake() {
        running?.abort()
    }

    private suspend fun loop(session: RedisSession) {
        var pending: List<TakenEntry>? = null // null: read the processing list first
        val backoff = Backoff()
        val outage = OutageCauses()
        while (true) {
            currentCoroutineContext().ensureActive()
            if (core.connections.isClosed) return
            try {
                var complete = true
                val taken = pending ?: peek(session)?.also { complete = it.second }?.first
                pending = if (taken == null) {
                    null // the host lease lapsed: wait for the heartbeat to re-claim it
                } else if (taken.isEmpty()) {
                    checkStepsWithoutScript(session)
                    val one = session.once { idleTake(it) }
                    // after an idle wait, the fenced peek comes first: this host may have been frozen in it
                    if (one == null) null else listOf(TakenEntry(one, one.size.toLong()))
                } else {
                    stepIds.clear()
                    val handling = System.nanoTime()
                    val parts = taken.map { handle(it, stepIds) }
                    val take = if (complete) seat.nextTake(parts.size, System.nanoTime() - handling) else 0
                    store(session, parts, take)?.takeIf { complete }
                }
                if (outage.end()) LOG.info("service '{}' reconnected to Redis", name)
                if (taken == null) delay(backoff.next()) else backoff.reset()
            } catch (e: CancellationException) {
                throw e
            } catch (e: HostingLost) {
                core.hostingLost(session, seat, e.holder)
                return
            } catch (e: VirtualMachineError) {
                replyFatal(session)
                LOG.error("service '{}' stops: {}", name, e.toString())
                throw e
            } catch (e: Throwable) {
                if (core.connections.isClosed) return
                currentCoroutineContext().ensureActive() // a cancelled run woken by [wake]: no outage
                if (outage.isNew(e)) {
                    if (e is JedisDataException && RedisPermissions.isRefusal(e)) {
                        LOG.error("service '{}' {}; retrying", name, describeFailure(e))
                    } else {
                        LOG.warn("service '{}' {}; retrying", name, describeFailure(e))
                    }
                }
                waitBehindStep = false
                pending = null
                delay(backoff.next())
            }
        }
    }

    /**
     * Before the first idle take of a service that may step lone requests without the script (see
     * [storeRequest]), checks once that its Redis user may send what that needs; if not, says so
     * once at ERROR and steps every request with the script, which needs none of it.
     */
    private fun checkStepsWithoutScript(session: RedisSession) {
        val step = requestStep ?: return
        if (step.permissionsChecked || seat.membership != null || core.connections.replicaAcks != null) return
        val refusal = session.once { step.checkPermissions(it) } ?: return
        session.abort() // perhaps left watching or inside a transaction
        LOG.error(
            "{}; it steps its calls with the script from now on, which costs Redis more per call",
            RedisPermissions.explain(refusal, core.redisUser, core.name(), "service '$name'").message,
        )
    }

    /**
     * Waits up to a second for an entry and moves it to the processing list; in the same round
     * trip, takes what it moved off the input's queue count (a block that then holds it for long
     * leaves room in the queue, as a step's take does) and, for a host of an unordered service,
     * checks in Redis that the host still has its seat ([HostingScripts.CHECK_SEATED]): `null` if
     * nothing came or what came went back to the input.
     */
    private fun idleTake(jedis: redis.clients.jedis.Jedis): ByteArray? {
        val membership = seat.membership
        // a service only called gets requests, which are not counted: a plain take, watched for the step without a script
        // (a host of an unordered service takes with the seat check behind, and its steps go with the script)
        if (!counted && membership == null) return requestStep!!.takeWatched(jedis, idleWaitArgument)
        val pipeline = jedis.pipelined()
        val moved = pipeline.blmove(input, processing, ListDirection.LEFT, ListDirection.RIGHT, seat.idleWaitSeconds)
        val countKeys = listOf(processing, queued)
        val countTaken = if (counted) Script.COUNT_IDLE_TAKE.queueBySha(pipeline, countKeys, emptyList()) else null
        val seatedKeys = membership?.let { (hosts, _) -> listOf(hosts, processing, input, queued) }
        val seatedArgs = membership?.let { (_, id) -> listOf(id, if (counted) ONE else ZERO) }
        val seated = seatedKeys?.let { HostingScripts.CHECK_SEATED.queueBySha(pipeline, it, seatedArgs!!) }
        pipeline.sync()
        val entry = moved.get()
        try {
            countTaken?.get()
        } catch (_: redis.clients.jedis.exceptions.JedisNoScriptException) {
            // Redis restarted and forgot it: the processing list still holds just what was moved
            Script.COUNT_IDLE_TAKE.run(jedis, countKeys, emptyList())
        }
        val movedBack = try {
            seated?.get()
        } catch (_: redis.clients.jedis.exceptions.JedisNoScriptException) {
            HostingScripts.CHECK_SEATED.run(jedis, seatedKeys!!, seatedArgs!!) // not loaded yet: checked right after
        }
        return if (movedBack is Long && movedBack > 0) null else entry
    }

    private fun describeFailure(e: Throwable): String = when {
        e is TooManyClients -> "cannot connect to Redis: ${e.message}"
        e is Exception && RedisConnections.isTransient(e) -> "lost Redis ($e)"
        e is JedisDataException && isOutOfMemory(e) ->
            "cannot store anything: Redis is out of memory (its maxmemory is reached: ${e.message})"
        e is JedisDataException && RedisPermissions.isRefusal(e) ->
            RedisPermissions.explain(e, core.redisUser, core.name(), "service '$name'").message!!
        else -> "cannot read its input ($e)"
    }

    /**
     * The head of the processing list (what a crash left), within the batch bounds; whether that
     * is all of it. `null` if nobody holds this service's host lease (it lapsed: the heartbeat
     * re-claims it); throws [HostingLost] if another instance holds it.
     */
    private fun peek(session: RedisSession): Pair<List<TakenEntry>, Boolean>? {
        val reply = session.once {
            Script.PEEK.run(
                it,
                listOf(processing, fence.lease),
                listOf(BATCH, rules.batchBytes, rules.maxEntryBytes).map { n -> n.toString().toByteArray(UTF_8) } +
                    fence.instance + (fence.claimMillis ?: NO_CLAIM),
            )
        } as List<*>
        if (reply[0] is ByteArray) { // {'FENCED', holder}
            val holder = (reply[1] as ByteArray).toString(UTF_8)
            if (holder.isNotEmpty()) throw HostingLost(holder)
            return null
        }
        val entries = reply.subList(1, reply.size).map { item ->
            if (item is ByteArray) TakenEntry(item, item.size.toLong())
            else (item as List<*>).let { TakenEntry(it[1] as ByteArray, it[0] as Long) }
        }
        return entries to (reply[0] == 1L)
    }

    /**
     * Stores the parts' results in one step and returns the entries taken next; if Redis refuses
     * the step for a reason of its content, stores the parts one at a time (dead-lettering any it
     * still refuses) and returns `null` (read the processing list again).
     */
    private suspend fun store(session: RedisSession, parts: List<Part>, take: Int): List<TakenEntry>? {
        val whole = if (parts.size == 1) parts[0].batch else StepBatch.combine(parts.map { it.batch })
        val output = parts.singleOrNull()?.output
        val stored = try {
            if (output != null && requestStep != null) return storeRequest(session, whole, parts[0].entry.bytes, output, take)
            runStep(session, whole, ack = parts.size, take = take) ?: return null
        } catch (e: JedisDataException) {
            if (!isEntryFault(e)) throw e
            storeOneByOne(session, parts, e)
            return null
        }
        whole.ids.forEach(recent::add)
        return stored.taken
    }

    /**
     * Stores a lone request's [output] with the request step (a service only called) and, when
     * this step takes ([take] > 0), waits for the next entry in the same write; returns the entries
     * taken next, or `null` to read the processing list again: after a blocking take in vain (the fenced
     * peek then comes first, as after an idle take), or after the general step stored what the
     * request step could not (a reply key it refused: the general step dead-letters the request),
     * or after a step that found the host lease held by nobody ([leaseLapsed]).
     */
    private suspend fun storeRequest(
        session: RedisSession,
        whole: StepBatch,
        entry: ByteArray,
        output: RequestOutput,
        take: Int,
    ): List<TakenEntry>? {
        val step = requestStep!!
        // no blocking take queued behind the step: with replicaAcks (every step is confirmed before the
        // service goes on), and for a host of an unordered service (its blocking take is the idle
        // take, which has the seat check behind it)
        val takeBehind = take > 0 && core.connections.replicaAcks == null && seat.membership == null
        if (takeBehind) storeWatched(session, step, whole, entry, output)?.let { return it.taken }
        val waitBehind = takeBehind && waitBehindStep
        waitBehindStep = false // until this step is stored
        val result = if (waitBehind) {
            session.once(null, idleWaitMillis) { step.executeThenWait(it, output, take, idleWaitArgument) }
        } else {
            session.once { step.execute(it, output, take) }
        }
        waitBehindStep = result is StepResult.Stored
        if (result is StepResult.Stray) {
            strayFound()
            return null
        }
        if (result is StepResult.Fenced) {
            if (result.holder.isNotEmpty()) throw HostingLost(result.holder)
            leaseLapsed()
            return null
        }
        if (result !is StepResult.Stored) {
            // a reply key the request step refused: the general step dead-letters the request
            runStep(session, whole, ack = 1, take = 0) ?: return null
            whole.ids.forEach(recent::add)
            return null
        }
        whole.ids.forEach(recent::add)
        return if (waitBehind && result.taken.isEmpty()) null else result.taken
    }

    /** What [storeWatched] took next: [taken], or `null` to read the processing list again. */
    private class Next(val taken: List<TakenEntry>?)

    /**
     * Stores a lone request's [output] without the script, if the take of [entry] was watched on
     * this connection ([RequestStep.storeWatched]), with the next blocking take behind it; `null` if
     * it could not be tried (store it with the script). A transaction Redis refused (the lease was
     * renewed, lost or lapsed since the take, or the target is not a list) is stored at once by the
     * general step on a connection of its own ([refusedSteps]), which answers the fence and
     * dead-letters as usual; the take already written behind it is read after that (what it moved
     * is in the processing list, read there next).
     */
    private suspend fun storeWatched(
        session: RedisSession,
        step: RequestStep,
        whole: StepBatch,
        entry: ByteArray,
        output: RequestOutput,
    ): Next? {
        var watched: redis.clients.jedis.Jedis? = null
        val stored = session.once(null, idleWaitMillis) { jedis ->
            if (!step.isWatched(jedis, entry)) return@once null
            watched = jedis
            step.storeWatched(jedis, output, idleWaitArgument)
        } ?: return null
        val storedAlone = stored || try {
            runStep(refusedSteps, whole, ack = 1, take = 0) != null // null: the lease lapsed, nothing stored
        } catch (e: Throwable) {
            session.abort() // the take written behind is not read: the connection cannot be used again
            throw e
        }
        if (storedAlone) whole.ids.forEach(recent::add)
        val moved = session.once(null, idleWaitMillis) { jedis -> if (jedis === watched) step.readTakeBehind(jedis) else null }
        return Next(if (!stored || moved == null) null else listOf(TakenEntry(moved, moved.size.toLong())))
    }

    /**
     * A refusal caused by what a step stores: not the connection, not the user's permissions, and
     * not a Redis out of memory (then nothing can be stored, not even a dead letter: the service
     * waits as in an outage rather than drop what it holds).
     */
    private fun isEntryFault(e: JedisDataException) =
        !RedisConnections.isTransient(e) && !RedisPermissions.isRefusal(e) && !isOutOfMemory(e)

    private suspend fun storeOneByOne(session: RedisSession, parts: List<Part>, cause: JedisDataException) {
        LOG.warn("service '{}': Redis refused a step of {} entries ({}); storing them one at a time", name, parts.size, cause.message)
        for (part in parts) {
            try {
                // null: the lease lapsed and nothing was stored; the rest is read again from the list
                runStep(session, part.batch, ack = 1, take = 0) ?: return
                part.batch.ids.forEach(recent::add)
            } catch (e: JedisDataException) {
                if (!isEntryFault(e)) throw e
                if (!deadLetterAlone(session, part, "Redis refused to store its results: ${e.message}")) return
            }
        }
    }

    /**
     * Dead-letters [part]'s entry alone; if Redis refuses even that, drops it with an ERROR (never a
     * loop). The drop is a step that stores nothing and acknowledges the entry, fenced like every
     * step: a host that lost its lease or seat meanwhile removes nothing from a list it no longer owns.
     * `false` if nothing was stored because the host lease lapsed ([leaseLapsed]).
     */
    private suspend fun deadLetterAlone(session: RedisSession, part: Part, reason: String): Boolean {
        val letter = empty.part()
        letter.dead(DeadLetter.encode(reason, part.entry))
        try {
            runStep(session, letter, ack = 1, take = 0) ?: return false
        } catch (e: JedisDataException) {
            if (!isEntryFault(e)) throw e
            runStep(session, empty.part(), ack = 1, take = 0) ?: return false
            LOG.error(
                "service '{}' dropped an entry: Redis refused both its results ({}) and its dead letter ({}); entry: {}",
                name, reason, e.message, DeadLetter.describe(part.entry),
            )
        }
        part.batch.ids.forEach(recent::add)
        return true
    }

    /**
     * Runs [batch]; refreshes a stale view of the output's readers, and waits while the queue it
     * feeds is full. `null` if the step stored nothing and the service must read its processing
     * list again: the step, which takes ([take] > 0), found a stray entry there ([strayFound]), or
     * nobody held the host lease ([leaseLapsed]).
     */
    private suspend fun runStep(session: RedisSession, batch: StepBatch, ack: Int, take: Int): StepResult.Stored? {
        var backoff: Backoff? = null
        while (true) {
            val result = session.once { jedis ->
                if (batch.publishes && output!!.view == null) output.refreshView(jedis, core.keys)
                batch.execute(jedis, ack, take)
            }
            when (result) {
                is StepResult.Stored -> {
                    if (backoff != null) LOG.info("service '{}' goes on: there is room again", name)
                    if (output != null && result.missed.isNotEmpty()) core.readerMisses.record(output, result.view, result.missed)
                    return result
                }
                is StepResult.Stale -> output!!.view = null
                is StepResult.Stray -> {
                    strayFound()
                    return null
                }
                is StepResult.Fenced -> {
                    if (result.holder.isNotEmpty()) throw HostingLost(result.holder)
                    leaseLapsed()
                    return null
                }
                is StepResult.Full -> {
                    if (backoff == null) {
                        LOG.warn(
                            "service '{}' waits: the queue of service '{}' holds {} values, its limit is {}",
                            name, core.keys.serviceOf(result.key), result.length, result.limit,
                        )
                    }
                    delay((backoff ?: Backoff().also { backoff = it }).next())
                    if (core.connections.isClosed) throw CoreClosedException(core.name())
                }
            }
        }
    }

    /**
     * Pushes the reply owed to a caller whose block threw a [VirtualMachineError], alone (nothing
     * acknowledged: the request stays in the processing list, as after a crash), so the caller
     * fails at once rather than at its call timeout. Best effort and bounded: one attempt, and any
     * throwable (another OutOfMemoryError) is ignored, for the error being thrown matters more.
     * The stack is unwound by now, so a StackOverflowError leaves room for it.
     */
    private fun replyFatal(session: RedisSession) {
        val (key, reply) = fatalReply ?: return
        fatalReply = null
        try {
            val step = empty.part()
            step.reply(key, reply)
            session.once { step.execute(it, ack = 0, take = 0) }
        } catch (_: Throwable) {
            // the caller waits for its timeout, as before
        }
    }

    /**
     * A step found an entry in the processing list that this run did not take: an earlier host's
     * blocking take that Redis ran after the host lease changed hands (a take written behind a step
     * that was then fenced, or one still waiting in Redis for a host that was frozen or cut off).
     * Nothing was stored; the service reads the list again and handles everything in it in order,
     * the entries it had handled once more, since their results were not stored.
     */
    private fun strayFound() {
        LOG.warn(
            "service '{}' found an entry in its processing list that it did not take (a take of an earlier host that " +
                "Redis ran after the host lease changed hands); it stored nothing and handles the list again, in order",
            name,
        )
    }

    /**
     * A step found this service's host lease held by nobody: it lapsed (this host was frozen or
     * cut off longer than the lease, or Redis lost it). Another host may have held it meanwhile,
     * handled entries this service holds and left others in the processing list, so the batch is
     * stale: nothing was stored, and the service reads the list again once it has re-claimed the
     * lease ([Script.PEEK] claims it, unless another host did first), handling the entries it had
     * handled once more if they are still there.
     */
    private fun leaseLapsed() {
        LOG.info("service '{}' found its host lease lapsed: it stored nothing, and reads its processing list again", name)
    }

    /** A step found this service's host lease held by another instance ([holder]): the service stops, storing nothing. */
    private class HostingLost(val holder: String) : Exception("the host lease is held by instance $holder")

    /**
     * One entry of a batch and what its handling stores; [output] when that is just one request's
     * one result (the reply, or the request for the next service), which a step of this entry
     * alone can store with the request step.
     */
    private class Part(val entry: TakenEntry, val batch: StepBatch) {
        var output: RequestOutput? = null
    }

    /**
     * Dead-letters [entry] for [reason] (its first bytes only if [prefix]) and logs it at WARN: the
     * first of a burst in full, then counted, at most one line per 10 s (a block's own failures are
     * logged by the error handler instead).
     */
    private fun deadLetter(step: StepBatch, reason: String, entry: TakenEntry, prefix: Boolean = false) {
        step.dead(if (prefix) DeadLetter.encodePrefix(reason, entry) else DeadLetter.encode(reason, entry))
        deadLetterLog.record("service '$name' dead-lettered entries", 1, reason) {
            LOG.warn(
                "service '{}' dead-lettered an entry: {} (see OptimusCore.deadLetters; further ones are counted, at most one " +
                    "line per {} s)",
                name, reason, RateLimitedLog.DEFAULT_SECONDS,
            )
        }
    }

    /** Handles one entry (a value, a request, or a frame of them); never throws but a [VirtualMachineError]. */
    private fun handle(entry: TakenEntry, batchIds: RecentIds): Part {
        val part = Part(entry, empty.part())
        val step = part.batch
        if (!entry.isWhole || entry.size > rules.maxEntryBytes) {
            deadLetter(step, "an entry of ${entry.size} bytes, over the limit of ${rules.maxEntryBytes}", entry, prefix = true)
            return part
        }
        val bounds = try {
            Frame.envelopeBounds(entry.bytes)
        } catch (e: CodecException) {
            deadLetter(step, "undecodable frame: ${e.message}", entry)
            return part
        }
        // a frame is acknowledged as a whole: every value of it is handled in this part
        for (k in 0 until bounds.size / 2) {
            val output = handleEnvelope(EnvelopeAt(entry, bounds[2 * k], bounds[2 * k + 1]), step, batchIds)
            if (bounds.size == 2) part.output = output
        }
        return part
    }

    /**
     * One envelope of a taken entry (a frame's, or the entry itself), read where it lies: its own
     * bytes are copied out only for a dead letter ([alone]).
     */
    private class EnvelopeAt(private val entry: TakenEntry, val offset: Int, val length: Int) {
        val bytes: ByteArray get() = entry.bytes

        /** The envelope as an entry of its own: [entry] itself if it is all of it, else a copy. */
        fun alone(): TakenEntry =
            if (offset == 0 && length == entry.bytes.size) entry
            else TakenEntry(entry.bytes.copyOfRange(offset, offset + length), length.toLong())
    }

    /**
     * Handles one envelope of an entry into [step]; never throws but a [VirtualMachineError].
     * Returns a request's one result, when that is all [step] got from it.
     */
    private fun handleEnvelope(at: EnvelopeAt, step: StepBatch, batchIds: RecentIds): RequestOutput? {
        val envelope = try {
            Envelope.parse(at.bytes, at.offset, at.length)
        } catch (e: CodecException) {
            deadLetter(step, "undecodable envelope: ${e.message}", at.alone())
            return null
        }
        // a duplicate of a value handled recently, or earlier in this batch
        if (envelope.id in recent || envelope.id in batchIds) return null
        batchIds.add(envelope.id)
        step.ids += envelope.id
        val replyTo = envelope.replyTo
        if (replyTo != null && !startsWith(replyTo, rules.replyPrefix)) {
            deadLetter(
                step,
                "refused request: its reply key ${printable(replyTo)} is outside this topology's reply namespace " +
                    "${rules.replyPrefix.toString(UTF_8)}*",
                at.alone(),
            )
            return null
        }
        val value = try {
            envelope.value(core, held)
        } catch (e: VirtualMachineError) {
            throw e
        } catch (e: Throwable) {
            // a CodecException (bytes it cannot or must not read), or anything a codec that broke
            // its contract throws: this entry's failure, never the service's (nor an outage to retry)
            val why = if (e is CodecException) e.message else "its codec threw $e (a codec should throw CodecException)"
            deadLetter(step, "cannot decode the value: $why", at.alone())
            if (replyTo != null) {
                step.reply(replyTo, Envelope.replyError(envelope.id, name, e.toString()))
            } else {
                core.reportFailure(name, at.alone().bytes, undecodable(e))
            }
            return null
        }
        when (envelope.kind) {
            Envelope.Kind.REQUEST -> return handleRequest(envelope, value, step)
            Envelope.Kind.VALUE -> handleValue(envelope, value, at, step)
            else -> deadLetter(step, "a ${envelope.kind} does not belong in a service's input", at.alone())
        }
        return null
    }

    /** Handles a request into [step]; returns its one result (also put in [step]). */
    private fun handleRequest(envelope: Envelope, value: Any?, step: StepBatch): RequestOutput {
        val replyTo = envelope.replyTo!!
        val running = core.runningRequest()
        try {
            var result: Any? = null
            running.id = envelope.id
            running.service = name
            running.active = true
            CallPaths.entered(envelope.id, onPath)
            try {
                logic.process(value) { result = it }
            } finally {
                CallPaths.left()
                running.active = false
                clearOwnInterrupt()
            }
            val payload = core.encode(result, held)
            return if (next != null) {
                Envelope.request(envelope.id, replyTo, payload).let { step.next(it); RequestOutput(next, it, isReply = false) }
            } else {
                Envelope.replyOk(envelope.id, payload).let { step.reply(replyTo, it); RequestOutput(replyTo, it, isReply = true) }
            }
        } catch (e: VirtualMachineError) {
            // the caller gets it promptly (see replyFatal), this service then ends
            fatalReply = replyTo to Envelope.replyError(envelope.id, name, e.toString())
            core.rememberFailure(envelope.id, e)
            throw e
        } catch (e: Throwable) {
            val failure = e as? ChainFailedException ?: ChainFailedException(name, e)
            // a CoreClosedException the block threw (it called a chain of a closed core) reaches a
            // caller in this process unchanged, as a ChainFailedException does (see Block)
            core.rememberFailure(envelope.id, if (e is CoreClosedException) e else failure)
            val reply = Envelope.replyError(envelope.id, failure.chainName(), failure.cause.toString())
            step.reply(replyTo, reply)
            return RequestOutput(replyTo, reply, isReply = true)
        }
    }

    private fun handleValue(envelope: Envelope, value: Any?, at: EnvelopeAt, step: StepBatch) {
        var attempts = 0
        while (true) {
            attempts++
            val outputs = ArrayList<ByteArray>(1) // each a value's envelope, its id written below
            try {
                // a null goes on to the next chain of a linked chain (as a null payload), as chains
                // pass nulls between blocks on every media; the last chain publishes nothing for it
                try {
                    logic.process(value) { output -> if (output != null || next != null) outputs += core.valueEnvelope(output, held) }
                } finally {
                    clearOwnInterrupt()
                }
            } catch (e: VirtualMachineError) {
                throw e
            } catch (e: Throwable) {
                if (core.connections.isClosed) return
                if (attempts <= core.retries) continue
                core.reportFailure(name, value ?: "null", e)
                step.dead(DeadLetter.encode("failed after $attempts attempt(s): $e", at.alone()))
                return
            }
            outputs.forEachIndexed { index, made ->
                val id = if (outputs.size == 1) envelope.id else ValueIds.derive(envelope.id, index)
                val forwarded = Envelope.withId(made, id)
                when {
                    next != null -> step.next(forwarded)
                    output != null -> step.publish(forwarded)
                }
            }
            return
        }
    }

    /** What the error handler gets for a value the codec could not decode: which service, which codec, why. */
    private fun undecodable(e: Throwable): PrimeException = PrimeException(
        "service '$name' could not decode a value with codec ${core.codec}: $e; the value is dead-lettered " +
            "(OptimusCore.deadLetters). Every process of the topology must use agreeing codecs, and a codec must " +
            "decode every value it encodes",
        e,
    )

    /**
     * Clears the interrupt flag the block set on this thread (it restored the flag of an
     * InterruptedException it caught) while the core is open: the service goes on, and neither its
     * next value's block nor another service sharing the thread starts with the flag. Cleared first,
     * then the core looked at: the interrupt of a close that comes meanwhile is kept.
     */
    private fun clearOwnInterrupt() = ServiceThreads.clearOwnInterrupt(closed)

    /** Whether the core is closed, made once for [clearOwnInterrupt]. */
    private val closed = BooleanSupplier { core.isClosed }

    override fun toString(): String = "service '$name'"

    companion object {
        /** The most values one step takes. */
        const val BATCH = 256
        private val LOG = LoggerFactory.getLogger(StageService::class.java)
        private val ONE = "1".toByteArray(UTF_8)
        private val ZERO = "0".toByteArray(UTF_8)

        /** [Script.PEEK]'s lease time for a seat whose lease the service does not claim itself. */
        private val NO_CLAIM = ByteArray(0)

        private fun isOutOfMemory(e: JedisDataException): Boolean =
            e.message?.let { it.startsWith("OOM") || " OOM " in it } == true

        private fun startsWith(bytes: ByteArray, prefix: ByteArray): Boolean =
            bytes.size >= prefix.size && (prefix.indices).all { bytes[it] == prefix[it] }

        /** A key for a message: at most 200 characters. */
        private fun printable(key: ByteArray): String = key.toString(UTF_8).take(200)
    }
}

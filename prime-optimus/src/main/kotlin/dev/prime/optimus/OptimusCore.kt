package dev.prime.optimus

import dev.prime.Block
import dev.prime.Chain
import dev.prime.ChainFailedException
import dev.prime.CoreClosedException
import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.FailureReport
import dev.prime.GenericService
import dev.prime.PrimeCore
import dev.prime.Reader
import dev.prime.Source
import dev.prime.ChainCompiler
import dev.prime.GenericServiceLoop
import dev.prime.SourceCompiler
import dev.prime.internal.Deadlines.boundedNanos
import dev.prime.internal.RateLimitedLog
import dev.prime.internal.ServiceThreads
import dev.prime.topology.Topology
import dev.prime.topology.TopologyNode
import kotlinx.coroutines.CancellationException
import kotlinx.coroutines.CoroutineName
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.ExecutorCoroutineDispatcher
import kotlinx.coroutines.Job
import kotlinx.coroutines.SupervisorJob
import kotlinx.coroutines.asCoroutineDispatcher
import kotlinx.coroutines.cancel
import kotlinx.coroutines.delay
import kotlinx.coroutines.launch
import kotlinx.coroutines.runBlocking
import kotlinx.coroutines.runInterruptible
import kotlinx.coroutines.withTimeoutOrNull
import org.slf4j.LoggerFactory
import redis.clients.jedis.Jedis
import redis.clients.jedis.Pipeline
import redis.clients.jedis.exceptions.JedisDataException
import redis.clients.jedis.params.ScanParams
import redis.clients.jedis.params.SetParams
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration
import java.time.Instant
import java.util.Collections
import java.util.UUID
import java.util.concurrent.ConcurrentHashMap
import java.util.concurrent.ConcurrentLinkedQueue
import java.util.concurrent.ExecutorService
import java.util.concurrent.Executors
import java.util.concurrent.atomic.AtomicInteger
import java.util.function.BooleanSupplier

/**
 * The Optimus media: every chain is a real service over Redis lists, so parts of one topology can
 * run in several processes on several machines.
 *
 * ```java
 * try (OptimusCore core = new OptimusCore()) {            // an embedded redis-server of its own
 *   Chain<Integer, Integer> twice = core.chain("twice", x -> 2 * x);
 *   core.start();
 *   int four = twice.toBlock().process(2);              // a remote call to the "twice" service
 * }
 * ```
 *
 * ## How it maps the topology to Redis
 * - A chain made of a block is one service: a coroutine that takes values from its input list
 *   and stores each result where it goes next. Linking chains re-routes lists (the first's
 *   results go straight to the second's input: no extra hop).
 * - [Chain.toBlock] is a remote call: it pushes the input with a reply address and waits for that
 *   call's own result; many threads may call at once.
 * - A source is a log of its newest values plus one list per reader; publishing pushes to all of
 *   them atomically. The log and plain readers' lists are trimmed to
 *   [CoreConfig.sourceRetention]; the input of a chain linked to the source is a queue, never
 *   trimmed (see "Delivery").
 * - Templates are the generic ones of [PrimeCore]: a template chain is one service whose block
 *   calls the services of the chains it was made of.
 *
 * ## Distribution
 * Every process declares the same topology, in the same order, with the same core name (the
 * name is the Redis namespace) and an agreeing codec; each one is told which services it hosts
 * ([Builder.hosts]); the others are remote. Values wait in Redis until a host takes them.
 *
 * ## Redis Cluster
 * With a `redis-cluster://` URL ([Builder.redis]) the core runs on a Redis Cluster: every key of
 * a topology carries its core name as the hash tag, so the topology lives in one hash slot on
 * one master (its atomic steps need that), and the topologies of many cores spread over the
 * masters. After a failover the core finds the promoted replica and goes on; [Builder.replicaAcks]
 * makes sure nothing it was told is stored was only on the failed master.
 *
 * ## Liveness, lost Redis data and the hosts of a service
 * - Each core holds a liveness lease in Redis (a key with an expiry, [Builder.leaseTime], 5 s by
 *   default) that a heartbeat renews every third of the lease time; its reader and reply lists
 *   are recorded as its own. When a process dies, any live process of the topology reclaims them
 *   within the lease time plus a heartbeat: its readers leave their sources and their lists are
 *   deleted. [close] removes them at once.
 * - [start] claims a host lease for every service the core hosts: a service has one host at a
 *   time. If another live process holds it, [start] waits up to one lease time for it to lapse
 *   (so a worker restarted after a crash takes over within the lease time), then fails with
 *   [IllegalStateException] ("already hosted by", naming the service and the holder). A process
 *   that finds its host lease taken (it was frozen longer than the lease) stops the service, logs
 *   a WARN and tells the error handler.
 * - That is the default, [Hosting.EXCLUSIVE]. [Builder.hosting] makes a service
 *   [Hosting.ORDERED] (one active host, other hosts stand by and take over within about a lease
 *   time, in order) or [Hosting.UNORDERED] (competing consumers: all hosts take values at once,
 *   each into a processing list of its own that a survivor gives back to the input when the host
 *   dies). All hosts of a service must declare the same mode, or [start] fails saying so.
 * - If Redis loses the topology's data (a restart without persistence, a failover to a replica
 *   that was behind), every live core notices within about one heartbeat, logs a WARN, counts it
 *   ([redisResets]) and declares again what it hosts and reads: the codec fingerprint, the
 *   registrations of its readers and of the services fed by sources (a list registered again
 *   gets the values the source retains), its ownership records and host leases. Values published
 *   after that arrive; values that were only in Redis (queued, unread, calls in flight, dead
 *   letters) are lost. What each Redis persistence mode keeps is tabled in the architecture docs.
 *
 * ## Delivery
 * - A service's input is a queue, not a retention window: nothing a service's queue accepted is
 *   dropped. Every value is processed at least once (a value pushed twice, e.g. by a retried
 *   publish, is recognised by its id and processed once, within the last 4096 ids a service
 *   handled) or dead-lettered with the reason. A value taken by a service stays in Redis until its
 *   result is stored, in the same atomic step (a Lua script, all keys of a topology in one hash
 *   slot); after a crash or a lost connection a service first finishes what it had taken. What
 *   survives a crash of Redis itself is what its persistence keeps (see docs/architecture.md).
 * - Queues are bounded ([Builder.queueLimit], per service or for all): a publish that would put a
 *   service's queue over its limit waits for room up to [Builder.publishTimeout], then throws
 *   [QueueFullException] and publishes nothing (a publish is all or nothing). A service whose
 *   next service's queue (a linked chain's internal hop, or a source feeding other services) is
 *   full holds its results and waits: internal hops never drop. A publish while Redis is
 *   unreachable gives up at the same timeout with [RedisUnavailableException].
 * - A plain [Reader] is a retention window ([CoreConfig.sourceRetention]): when it falls further
 *   behind, the oldest values it has not read are dropped; [Reader.missed] counts them, and the
 *   publishing process logs a WARN with the count, at most once per reader every 10 s.
 * - Dead letters ([deadLetters]): bytes that cannot be decoded, values whose block failed (after
 *   [Builder.retries]), entries above [Builder.maxValueBytes] (only their first KiB is kept),
 *   requests whose reply key is not one of this topology's reply lists, and entries whose results
 *   Redis refused to store (WRONGTYPE, a script error: the step is redone one entry at a
 *   time to find the one at fault). The service goes on. At most [Builder.deadLetterLimit] are
 *   kept per service; older ones are dropped and counted ([trimmedDeadLetters]). A Redis out of
 *   memory (`maxmemory` reached) or a missing permission is waited out like an outage, with a
 *   log line: nothing is dropped for it.
 * - A Redis that evicts keys at its `maxmemory` (a `maxmemory-policy` other than `noeviction`)
 *   may delete what these promises rest on: `allkeys-*` any key (queues, values in flight),
 *   `volatile-*` the keys with an expiry (the leases: live instances and hosts are taken for
 *   dead). [start] reads `INFO memory` (on a Redis Cluster, of the master of the topology's slot)
 *   and, if `maxmemory` is set and the policy is not `noeviction`, logs one WARN naming the policy,
 *   the `maxmemory`, what it may delete and the fix (`CONFIG SET maxmemory-policy noeviction`).
 *   A Redis user without `info`, or a Redis out of reach at that moment, skips the check (one
 *   attempt, no WARN); [start] goes on as without it.
 * - A Redis that does not fit fails or says so: [start] fails at once on a Redis without `LMOVE`
 *   or `BLMOVE` (it needs Redis 6.2 or newer); on a read-only replica's URL the core waits as in an
 *   outage and logs one WARN to give the master's URL; a Redis at its `maxclients` fails the
 *   operation that needed a new connection, saying to raise `maxclients`.
 * - A block's throwable never stops a service (anything but a [VirtualMachineError]): the error
 *   handler receives the service's name, the input and the block's own throwable.
 * - Values above [Builder.maxValueBytes] are refused where they are given, at publish or call
 *   ([ValueTooLargeException]); a service takes at most 256 values or 8 MiB per step.
 * - Values that are ready together (one [publishAll], one service step's outputs) travel as one
 *   Redis entry, a frame of at most 256 values and 1 MiB; nothing waits to fill a frame, so a
 *   lone value goes out at once. A frame is acknowledged whole and redelivered whole after a
 *   crash; duplicates are still skipped per value. Queue limits and reader retention count
 *   values, not entries (see docs/architecture.md, "Frames").
 * - Reply lists expire (10 minutes or twice the call timeout, whichever is longer) after each
 *   reply pushed to them, so replies to callers that died do not stay.
 * - [close] closes every connection, which wakes every blocked call, and leaves no thread.
 *
 * Threading: like every core, declaring is thread-safe; blocks of hosted services run on the
 * core's threads (`prime-<core>-optimus-<n>`), one value at a time per service; one of those
 * threads is the heartbeat, from the first registration or [start] until [close].
 */
public class OptimusCore private constructor(config: CoreConfig, settings: Settings) : PrimeCore("optimus", config) {

    /** A core on an embedded Redis of its own (see [EmbeddedRedis]), hosting every service. */
    public constructor() : this(CoreConfig.defaults())

    /** A core with [config], on an embedded Redis of its own, hosting every service. */
    public constructor(config: CoreConfig) : this(config, Settings())

    private val embedded: EmbeddedRedis?
    private val endpoint: RedisTarget
    private val givenRedisUrl: String? = settings.redisUrl
    private val replicaAcks: ReplicaAcks? = settings.replicaAcks
    internal val keys: Keys = Keys(name())
    internal val codec: OptimusCodec = settings.codec ?: KryoCodec.standard()

    /** [codec] if it is a [KryoCodec], which encodes into an envelope and decodes in place; else `null`. */
    private val kryoCodec: KryoCodec? = codec as? KryoCodec
    internal val declaredTypes: DeclaredTypes = DeclaredTypes()
    internal val connections: RedisConnections
    internal val ids: ValueIds = ValueIds()
    internal val retries: Int = settings.retries
    internal val callTimeout: Duration? = settings.callTimeout
    private val publishTimeout: Duration = settings.publishTimeout ?: config.publishTimeout()
    private val maxValueBytes: Int = settings.maxValueBytes
    private val queueLimit: Int = settings.queueLimit
    private val queueLimits: Map<String, Int> = settings.queueLimits
    internal val stepRules: StepRules = StepRules(
        keys.replyPrefix,
        maxOf(MIN_REPLY_TTL.toMillis(), 2 * (boundedNanos(callTimeout ?: MIN_REPLY_TTL) / 1_000_000)),
        settings.deadLetterLimit,
        // a value at the limit, in an envelope with the longest reply key, alone in a frame
        (maxValueBytes.toLong() + ENVELOPE_OVERHEAD + Frame.HEADER + Frame.PER_VALUE).coerceAtMost(Int.MAX_VALUE.toLong()).toInt(),
        settings.batchBytes,
        { input -> queueLimitOf(keys.serviceOf(input)) },
        // a frame of many values stays within what a consumer reads whole (the entry size limit)
        minOf(settings.frameBytes.toLong(), maxValueBytes.toLong() + ENVELOPE_OVERHEAD).toInt(),
    )
    internal val readerMisses: ReaderMisses = ReaderMisses(name())

    /** The values readers skipped because the codec could not decode them: bursts logged once, then counted. */
    internal val readerSkips: RateLimitedLog = RateLimitedLog(OptimusReader::class.java.name)
    private val hosts: Set<String>? = settings.hosts
    private val instance = UUID.randomUUID().toString()

    /** This core instance's id in the topology (random per core), as its leases and seats name it. */
    internal val instanceId: String get() = instance

    private val services = ConcurrentHashMap<String, StageService>()
    private val genericServices = ConcurrentHashMap<String, GenericServiceLoop>() // hosted here only
    private val launched: MutableSet<String> = ConcurrentHashMap.newKeySet()
    private val readers: MutableSet<Pair<SourceKeys, ByteArray>> = ConcurrentHashMap.newKeySet()
    private val subscriptions = ConcurrentLinkedQueue<EventBlock.Subscription>()
    private val idleSlots = ConcurrentLinkedQueue<CallerSlot>()
    private val allSlots = ConcurrentLinkedQueue<CallerSlot>()
    private val slotNumbers = AtomicInteger()
    private val publishers = ConcurrentLinkedQueue<RedisSession>()
    /** The services of each chain bound for calls ([bindForCalls]), by chain name. */
    private val calledServices = ConcurrentHashMap<String, List<String>>()

    /** The remote calls made whose [SelfCalls] are not looked for yet ([resolveSelfCalls]). */
    private val unresolvedCalls = ConcurrentLinkedQueue<RemoteCall<*, *>>()
    private val failures = Collections.synchronizedMap(object : LinkedHashMap<Long, Throwable>() {
        override fun removeEldestEntry(eldest: MutableMap.MutableEntry<Long, Throwable>?) = size > FAILURES_KEPT
    })

    /** Whether this core is closed, the mark of its own threads ([ServiceThreads.markOwnThread]). */
    private val closedMark = BooleanSupplier { isClosed }
    private val threadNumbers = AtomicInteger()
    private val threads = ConcurrentLinkedQueue<Thread>()
    private val executor: ExecutorService = Executors.newCachedThreadPool { task ->
        val owner = this
        Thread({
            ownerOfThread.set(owner)
            ServiceThreads.markOwnThread(owner.closedMark)
            task.run()
        }, "prime-${name()}-optimus-${threadNumbers.incrementAndGet()}").apply {
            isDaemon = true
            threads += this
        }
    }
    /**
     * This core's own threads running a generic service's loop: the cancel of [close] interrupts
     * them (they run interruptibly) and their `shutdown()` then runs with the flag cleared, which a
     * second interrupt must not cut short; [close] interrupts every other thread of the core.
     */
    private val inGenericLoops: MutableSet<Thread> = ConcurrentHashMap.newKeySet()
    private val dispatcher: ExecutorCoroutineDispatcher = executor.asCoroutineDispatcher()
    private val supervisor = SupervisorJob()
    private val scope = CoroutineScope(supervisor + dispatcher + CoroutineName("optimus-${name()}"))

    init {
        val url = settings.redisUrl
        embedded = if (url == null) EmbeddedRedis.start() else null
        endpoint = RedisTarget.parse(url ?: embedded!!.uri, keys)
        connections = RedisConnections(endpoint, name(), settings.replicaAcks)
        try {
            RedisSession(connections).use { it.once { jedis -> jedis.ping() } }
        } catch (e: Exception) {
            connections.closeAll() // a cluster's slot map too
            shutdownResources()
            throw dev.prime.PrimeException("cannot reach Redis at $endpoint: $e", e)
        }
    }

    private val hostLeases = HostLeases(keys, connections, instance, settings.leaseTime) { services.containsKey(it) }
    private val leaseTime: Duration = settings.leaseTime
    private val sharedHosting = SharedHosting(keys, instance, settings.leaseTime, settings.hostingModes)
    private val hostedJobs = ConcurrentHashMap<String, Job>()

    /** The combinators and timers whose host lease [hostOnCoreThreads] claimed after start. */
    private val coreThreadClaims: MutableSet<String> = ConcurrentHashMap.newKeySet()
    private val notRunning: MutableSet<String> = ConcurrentHashMap.newKeySet() // hosted, but refused or taken over
    private val declarations = Redeclaration(
        keys, name(), instance, codec.fingerprint(), hostLeases,
        readers = { readers },
        replyLists = { (1..slotNumbers.get()).map(::replyKey) },
        register = ::registerOnce,
        lostHosting = ::stopLostService,
        renewShared = ::renewSharedHosting,
    )
    private val liveness = Liveness(keys, connections, instance, settings.leaseTime, executor::execute, declarations)

    /** The URL of the Redis this core uses (password hidden). */
    public val redisUrl: String get() = endpoint.toString()

    /** The Redis user this core logs in as (`null`: the default user), for messages. */
    internal val redisUser: String? get() = endpoint.user

    // ------------------------------------------------------------------ chains and sources

    /** Chains compile to the services they are made of ([OptimusChainCompiler]). */
    override fun chainCompiler(): ChainCompiler<*> = OptimusChainCompiler(this)

    /** Sources are Redis lists, and services of them Redis services ([OptimusSourceCompiler]). */
    override fun sourceCompiler(): SourceCompiler<*> = OptimusSourceCompiler(this)

    /** A source of this core publishing what [events] publishes. */
    internal fun <T> eventSource(name: String, events: EventBlock<T>): Source<T> {
        val source = OptimusSource<T>(this, name, ofEvents = true)
        subscriptions += events.subscribe { value ->
            try {
                publish(source.keys, listOf(Envelope.withId(valueEnvelope(value), ids.next())))
            } catch (_: CoreClosedException) {
                // the core closed while this value was on its way: nobody can read it any more
            }
        }
        return source
    }

    /**
     * Binds [stages] (one service, or a linked chain's services) to read [source]; returns their
     * output source, named [output], or `null` if they publish nothing (a listener).
     */
    internal fun serviceOn(source: OptimusSource<*>, stages: List<StageSpec>, output: String?, chain: String = stages.first().name): OptimusSource<Any>? {
        val published = output?.let { OptimusSource<Any>(this, it, ofEvents = false) }
        interruptibleInOutage({ "linking to source '${source.name()}'" }, waitedFor = WAITED_FOR_REDIS_OR_LEASE, abortsWaitsForAnswers = true) {
            bindToSource(chain, source, stages, published)
        }
        return published
    }

    /**
     * Publishes [values] to [source] in one atomic step (one round trip), in order: the fast way
     * to feed a source at high rates, where [EventBlock.publish] costs a round trip per value.
     * All or nothing: if a service queue fed by the source has no room for all of them within
     * [Builder.publishTimeout], none is published; a refused value (`null`, too large, of a type
     * the codec does not allow) is found before anything is sent, so none is published then
     * either. An empty [values] publishes nothing and costs no round trip (it is still refused
     * before [start], like any publish).
     *
     * [source] is the source of an [EventBlock] of this core ([dev.prime.PrimeCore.source]), as
     * [EventBlock.publish] publishes to: the output of a service (a chain linked to a source, a
     * filter, a flat-map) is only ever published by that service, and a combinator's output or a
     * timer only by the core; they are refused.
     *
     * From Java it is `publishAll(source, values)`, which refuses a `null` for either with a
     * [NullPointerException] naming it and saying what to pass, as the core's other declarations
     * refuse a `null` (rather than with the message Kotlin makes for a non-null parameter; Kotlin
     * callers cannot pass one); a `null` value among [values] is an [IllegalArgumentException]
     * naming its position and saying what to publish instead.
     *
     * @throws NullPointerException if [source] or [values] is `null` (from Java)
     * @throws IllegalArgumentException if the source is not an Optimus source of this core, or is
     *     a service's, a combinator's or a timer's output, or a value is `null` or of a type the
     *     codec does not allow
     * @throws ValueTooLargeException if a value encodes to more than [Builder.maxValueBytes]
     * @throws QueueFullException if a service queue stays too full for the values until the publish timeout
     * @throws RedisUnavailableException if Redis stays unreachable until the publish timeout
     * @throws IllegalStateException if the core is not started yet, whatever [values] holds
     * @throws CoreClosedException if the core is closed
     */
    @JvmSynthetic // Java calls publishAllFromJava, under the name publishAll
    @JvmName("publishAllOf")
    public fun <T> publishAll(source: Source<T>, values: Iterable<T>) {
        checkOpen()
        val target = requireNotNull(sourcePart(source, OptimusSource::class.java)) { "$source is not a source of $this" }
        require(target.ofEvents) {
            "source '${source.name()}' of core '${name()}' is the output of a service (a chain linked to a source, a " +
                "filter or a flat-map): only that service publishes to it. Publish to the event block's source that " +
                "feeds it instead (the Source core.source(events) returned), with publishAll or EventBlock.publish"
        }
        require(isProgramsEventSource(target)) {
            "source '${source.name()}' of core '${name()}' is made by the core (a combinator such as withLatestFrom or " +
                "sample, or a timer): only the core publishes to it. Publish to the event block's source that feeds " +
                "it instead (the Source core.source(events) returned), with publishAll or EventBlock.publish"
        }
        checkStarted("publishing to an Optimus source")
        val keys = target.keys
        val began = Instant.now()
        val beganNanos = System.nanoTime()
        val published = values.toList()
        val envelopes = holdCodec().use { held ->
            published.mapIndexed { index, value ->
                requireNotNull(value) {
                    "publishAll(source, values): value $index of values is null, and sources carry no null values; " +
                        "publish an Optional or a sentinel instead (nothing was published)"
                }
                Envelope.withId(valueEnvelope(value, held), ids.next())
            }
        }
        if (envelopes.isEmpty()) return
        var accepted = false
        try {
            publish(keys, envelopes)
            accepted = true
        } finally {
            // recorded and metered as what the source's event block publishes
            publishedTogether(source.name(), published, began, beganNanos, accepted)
        }
    }

    /**
     * [publishAll] as Java sees it, `publishAll(source, values)`: internal, so not part of the
     * Kotlin API, and with nullable parameters, so that a `null` from Java is refused by the checks
     * here, naming the parameter and what to pass, not by the check Kotlin makes of a non-null
     * parameter.
     */
    @JvmName("publishAll")
    internal fun <T> publishAllFromJava(source: Source<T>?, values: Iterable<T>?) {
        if (source == null) {
            throw NullPointerException(
                "publishAll(source, values): source must not be null; pass the Source that core.source(events) returned",
            )
        }
        if (values == null) {
            throw NullPointerException(
                "publishAll(source, values): values must not be null; pass an empty list to publish nothing",
            )
        }
        publishAll(source, values)
    }

    /**
     * Whether the event block that publishes to [source] is the program's: its node is an event
     * source, not a combinator or a timer. Looked up in the topology at the first [publishAll] to it.
     */
    private fun isProgramsEventSource(source: OptimusSource<*>): Boolean = source.programsEvents
        ?: (topology().node(source.name()).orElse(null) is TopologyNode.EventSource).also { source.programsEvents = it }

    // ------------------------------------------------------------------ generic services

    /**
     * Runs a generic service only if this process hosts it ([Builder.hosts]): like every service it
     * has one host at a time (a host lease, claimed at [start]), so of several processes that
     * declare it exactly one runs it. It runs on a thread of this core; [close], or losing its host
     * lease, interrupts it. Declared after [start], it claims its lease at once (waiting for Redis in
     * an outage: interrupted there, a [dev.prime.PrimeException] that says so, the flag kept); a
     * declaration that fails leaves nothing behind, so it can be made again.
     */
    override fun runGenericService(name: String, service: GenericService) {
        if (!isHosted(name)) return // another process runs it
        val loop = GenericServiceLoop(name, service, config().errorHandler()) { isClosed || name in notRunning }
        genericServices[name] = loop
        if (!isStarted) return
        val wasRunning = name !in notRunning
        try {
            interruptibleInOutage({ "declaring generic service '$name'" }, waitedFor = WAITED_FOR_REDIS_OR_LEASE, abortsWaitsForAnswers = true) {
                launchHosted(name) { runInterruptible { runGenericLoop(loop) } }
            }
        } catch (e: Throwable) {
            // the declaration fails and is forgotten: nothing of it stays, so it can be made again
            genericServices.remove(name, loop)
            if (wasRunning) notRunning -= name
            throw e
        }
    }

    // ------------------------------------------------------------------ dead letters

    /**
     * The values service [service] gave up on, oldest first (see [DeadLetter]). While Redis is
     * unreachable it waits for Redis, at most 10 s.
     *
     * @throws RedisUnavailableException if Redis stays unreachable for 10 s
     * @throws dev.prime.PrimeException if the thread is interrupted while it waits for Redis (the flag is kept)
     * @throws CoreClosedException if the core is closed
     */
    public fun deadLetters(service: String): List<DeadLetter> {
        checkOpen()
        return interruptibleInOutage({ "reading the dead letters of service '$service'" }, waitedFor = WAITED_FOR_ANSWER, abortsWaitsForAnswers = true, flagSetBeforeEnds = false) {
            withSession { session -> session.retryingUntil(deadLettersDeadline(), "read the dead letters of service '$service'") { it.lrange(keys.deadLetters(service), 0, -1) } }
        }.map { DeadLetter.decode(service, it) }
    }

    /**
     * How many dead letters of [service] were dropped, oldest first, to keep its list within
     * [Builder.deadLetterLimit] (since the topology's Redis data was created; [clearDeadLetters]
     * does not reset it). While Redis is unreachable it waits for Redis, at most 10 s.
     *
     * @throws RedisUnavailableException if Redis stays unreachable for 10 s
     * @throws dev.prime.PrimeException if the thread is interrupted while it waits for Redis (the flag is kept)
     * @throws CoreClosedException if the core is closed
     */
    public fun trimmedDeadLetters(service: String): Long {
        checkOpen()
        return interruptibleInOutage(
            { "reading how many dead letters of service '$service' were dropped" },
            waitedFor = WAITED_FOR_ANSWER,
            abortsWaitsForAnswers = true,
            flagSetBeforeEnds = false,
        ) {
            withSession("read the dead-letter count of service '$service'") { session ->
                session.retryingUntil(deadLettersDeadline(), "read the dead-letter count of service '$service'") {
                    it.get(keys.deadLettersTrimmed(service))
                }
            }
        }?.toString(UTF_8)?.toLong() ?: 0L
    }

    /**
     * Deletes the dead letters of [service]; returns how many there were. While Redis is
     * unreachable it waits for Redis, at most 10 s.
     *
     * @throws RedisUnavailableException if Redis stays unreachable for 10 s (an attempt whose answer
     *   was lost may have deleted them)
     * @throws dev.prime.PrimeException if the thread is interrupted while it waits for Redis (the
     *   flag is kept; an attempt whose answer was lost may have deleted them)
     * @throws CoreClosedException if the core is closed
     */
    public fun clearDeadLetters(service: String): Int {
        checkOpen()
        return interruptibleInOutage(
            { "clearing the dead letters of service '$service'" },
            "; an attempt whose answer was lost may have cleared them",
            WAITED_FOR_ANSWER,
            abortsWaitsForAnswers = true,
            flagSetBeforeEnds = false,
        ) {
            withSession { session ->
                session.retryingUntil(deadLettersDeadline(), "clear the dead letters of service '$service'") { jedis ->
                    val transaction = jedis.multi()
                    val length = transaction.llen(keys.deadLetters(service))
                    transaction.del(keys.deadLetters(service))
                    transaction.exec()
                    length.get().toInt()
                }
            }
        }
    }

    /**
     * When a read or deletion of dead letters that begins now gives up waiting for Redis: a tool or
     * a dashboard that asks during an outage gets an answer or a [RedisUnavailableException], never
     * a wait as long as the outage.
     */
    private fun deadLettersDeadline(): Long = System.nanoTime() + DEAD_LETTERS_TIMEOUT.toNanos()

    // ------------------------------------------------------------------ retiring a topology

    /**
     * Deletes every Redis key of this core's topology, `prime:{<name>}:*`: what its sources
     * retain, the services' queues and processing lists, dead letters, readers' lists, leases and
     * sequence numbers. Optimus keeps these after [close] on purpose (a restarted process goes on
     * where the last one stopped); delete them for a topology you retire, or after a test that
     * gave its run a topology of its own on a shared Redis (`@PrimeTest` does so after every run).
     *
     * Only on a closed core, and only once no other process runs the topology on this Redis: one
     * whose liveness lease lives (from its first reader or [start] until its [close], or until the
     * lease lapses after it died) makes this refuse and delete nothing. Keys of other topologies
     * are not touched (they have other names). A core on an embedded Redis of its own has nothing
     * to delete: its data went with its server at [close]; this returns 0.
     *
     * The deletion is not atomic: it scans the topology's keys (the Redis user needs `scan` besides
     * the commands a core needs) and deletes them in batches, retrying on a new connection while
     * Redis is unreachable, for at most 10 s; an interrupt ends that wait at once with a
     * [dev.prime.PrimeException] and keeps the flag (a command already sent runs to its reply or
     * its timeout first). Run again, it deletes what is left. A process that
     * starts the topology while it runs may find some keys gone. With [Builder.replicaAcks] every
     * step is confirmed by the replicas, as every operation of the core is.
     *
     * @return how many keys were deleted
     * @throws IllegalStateException if the core is not closed, or another process runs the
     *   topology (the message names it)
     * @throws RedisUnavailableException if Redis cannot be reached for 10 s
     * @throws dev.prime.PrimeException if the Redis user lacks `scan`, `del` or the topology's keys
     *   (the message says what to grant)
     */
    public fun deleteKeys(): Long {
        check(isClosed) {
            "core '${name()}' is not closed: close() it before deleteKeys() (its services and readers use those keys)"
        }
        val url = givenRedisUrl ?: return 0
        val target = RedisTarget.parse(url, keys)
        val connections = RedisConnections(target, name(), replicaAcks) // confirmed like every operation of the core
        val deadline = System.nanoTime() + DELETE_KEYS_TIMEOUT.toNanos()
        val what = "delete the keys of topology '${name()}'"
        var deleted = 0L
        try {
            explainingRefusals(what) {
                RedisSession(connections).use { session ->
                    session.retryingUntil(deadline, what) { jedis ->
                        val running = jedis.smembers(keys.instances)
                            .mapNotNull { jedis.get(keys.instanceLease(it.toString(UTF_8)))?.toString(UTF_8) }
                        check(running.isEmpty()) {
                            "topology '${name()}' is still run by ${running.size} other process(es) on this Redis " +
                                "(${running.sorted().joinToString()}): close them before deleteKeys(), or if they died, " +
                                "wait until their leases lapse (leaseTime, ${leaseTime.toMillis()} ms here); nothing was deleted"
                        }
                        val match = ScanParams().match(keys.all).count(DELETE_KEYS_BATCH)
                        var cursor = ScanParams.SCAN_POINTER_START_BINARY
                        do {
                            val page = jedis.scan(cursor, match)
                            if (page.result.isNotEmpty()) deleted += jedis.del(*page.result.toTypedArray())
                            cursor = page.cursorAsBytes
                        } while (!cursor.contentEquals(ScanParams.SCAN_POINTER_START_BINARY))
                    }
                }
            }
        } finally {
            connections.closeAll()
        }
        return deleted
    }

    /**
     * Whether this process runs [service]: it hosts it ([Builder.hosts]; all services by default)
     * and was not refused it, or lost it, to another live instance (see [start]).
     */
    override fun isHostedHere(service: String): Boolean = isHosted(service) && service !in notRunning

    /** The request each service thread runs a block for now (see [runningRequest], [callerGaveUp]). */
    private val runningRequests = ThreadLocal.withInitial { RunningRequest() }

    /** The current thread's record of the request it runs a block for; a service sets it around each request. */
    internal fun runningRequest(): RunningRequest = runningRequests.get()

    /**
     * Refuses a call to chain [chainName], whose own services are [services], made on a thread
     * that runs a request's block of one of them (a chain that calls itself, or a linked chain
     * called from its later chain): that service takes one request at a time (one host, one
     * thread, unless it is [Hosting.UNORDERED]), so the call would wait for the request that makes
     * it, until [Builder.callTimeout]. Costs a call one thread-local read (a thread's first also makes its record).
     */
    internal fun refuseCallThroughItself(chainName: String, services: Set<String>) {
        val running = runningRequests.get()
        if (!running.active) return
        val service = running.service ?: return
        if (service !in services || sharedHosting.modeOf(service) == Hosting.UNORDERED) return
        throw IllegalStateException(
            "chain '$chainName' was called from inside itself: the block of service '$service', which the call " +
                "runs through, called it on the thread that runs it. On Optimus a service takes one request at a " +
                "time, so the call would wait for itself. For recursion, let the block call a method of its own " +
                "rather than its chain",
        )
    }

    /**
     * Refuses a call to chain [chainName], whose own services are [serviceKeys] (each by its
     * [CallPaths] name), if one of them waits, in this process, for the request whose block makes
     * the call ([path], [CallPaths.current]): a chain called back by a chain its block calls, a
     * template called by its part, a chain called through another core of its topology. That
     * service takes one request at a time (unless it is [Hosting.UNORDERED]), so the call would
     * wait for itself until [Builder.callTimeout]. Run only on a thread that runs a request's block.
     */
    internal fun refuseCallOnItsOwnPath(chainName: String, serviceKeys: Map<String, String>, path: CallPath) {
        for ((service, key) in serviceKeys) {
            if (!path.waits(key) || sharedHosting.modeOf(service) == Hosting.UNORDERED) continue
            val running = runningRequests.get().takeIf { it.active }?.service
            throw IllegalStateException(
                "chain '$chainName' was called from inside itself: its service '$service' is waiting for the call " +
                    "that led to this one (" + (running?.let { "made by the block of service '$it', " } ?: "") +
                    "through a chain its block called, a template's part or another core's block), and on Optimus a " +
                    "service takes one request at a time, so the call would wait for itself. For recursion, let the " +
                    "block call a method of its own rather than a chain that calls back",
            )
        }
    }

    /**
     * Runs [call], a call of this core's chain. Made on an own thread of another Optimus core (a
     * block of that core's service calling this core's chain through its `toBlock()`), the call
     * waits on this core's connections, which that core's [close] does not close: that close
     * interrupts every thread of its own after closing its connections, which ends such a call
     * under way at once (nothing the block returns could then be stored, and the value stays in its
     * processing list), rather than after `shutdownTimeout`. A call made on such a thread once that
     * core is closed (after a block that swallowed the close's interrupt) sets the flag itself: it
     * fails as an interrupted one.
     */
    internal inline fun <T> callOfAnotherCore(call: () -> T): T {
        val owner = ownerOfCurrentThread()
        if (owner != null && owner !== this && owner.isClosed) Thread.currentThread().interrupt()
        return call()
    }

    /** The Optimus core whose own thread the current thread is, or `null`. */
    internal fun ownerOfCurrentThread(): OptimusCore? = ownerOfThread.get()

    /**
     * Clears the interrupt flag of the calling thread if it is an own thread of an open core of
     * this JVM, of any media ([ServiceThreads.markOwnThread]: a service, a template, a listener
     * of an Optimus core, this one or another, a Liberty or Radiant core's service), and this core
     * is open too, and says whether it did. Such a flag was left by a block (an `ifThenElse`
     * condition, a block that interrupted itself before calling a chain): while the core is open,
     * the services clear the flag before their next value, and only its close ends them, or, for
     * an Optimus generic service, the loss of its host lease to another process (it is interrupted
     * then, and finishes a call it is making before it stops; what it stores is fenced by the
     * lease). A call of a chain made then is made without the flag, as where the called blocks run
     * inline (Liberty, Radiant) and a call never waits for a reply; the caller sets the flag again
     * after the call. A close that interrupts the thread meanwhile still ends the call: this core's
     * closes the call's connections, and the flag that either core's close sets ends the wait. A
     * close of the thread's core that began before the flag was cleared may have set it: the flag
     * is kept then, and the call fails as an interrupted one. A thread of no core (a user's) keeps
     * its flag, and its call fails as interrupted.
     */
    internal fun clearFlagLeftByABlock(): Boolean {
        if (!Thread.currentThread().isInterrupted || isClosed) return false
        return ServiceThreads.clearFlagLeftOnOwnThread()
    }

    /**
     * Whether the caller of the request this service thread runs a block for gave up after the
     * service took it: its mark ([AbandonedCalls]) is in Redis. False on a thread that runs no
     * request (a value, a caller's own thread), and when Redis cannot tell now.
     */
    override fun callerGaveUp(): Boolean {
        val running = runningRequests.get()
        if (!running.active) return false
        return try {
            withSession("checking whether a caller gave up") { session ->
                session.readOnce { it.exists(keys.abandonedCall(running.id)) }
            }
        } catch (_: RuntimeException) {
            false // Redis is unreachable or the core closed: the wait's other checks decide
        }
    }

    /** The start line names the Redis, its password redacted ([redisUrl]). */
    override fun startDetails(): String = " with Redis $redisUrl"

    // ------------------------------------------------------------------ liveness

    /**
     * How many times this core found that Redis lost the topology's data (it restarted without
     * persistence, or failed over to a replica that was behind). Each time the core logged a
     * WARN and declared again what it hosts and reads; values that were only in Redis are gone.
     */
    public fun redisResets(): Long = liveness.resets

    // ------------------------------------------------------------------ lifecycle

    /**
     * Declares and claims in Redis what this process hosts and reads, then launches its services;
     * it waits for Redis in an outage, and for another process's host lease to lapse. Interrupted
     * while it waits, it fails with a [dev.prime.PrimeException] that says so (the flag kept), not
     * with the close's [CoreClosedException]: the core is open, but failed to start ([PrimeCore.start]), so close it.
     */
    override fun onStart(): Unit = interruptibleInOutage(
        { "start() of core '${name()}'" },
        "; the core started only in part: close it and make a new one",
        WAITED_FOR_REDIS_OR_LEASE,
        abortsWaitsForAnswers = true,
    ) {
        startHere()
    }

    private fun startHere() {
        declaredTypes.check(name(), codec)
        resolveSelfCalls()
        withSession { session -> CommandCheck.check(session, keys, name(), redisUrl) }
        beginLiveness()
        checkCodecAgreement()
        declarations.codecDeclared = true
        withSession { session -> EvictionCheck.check(session, name()) }
        try {
            hosts?.let { wanted ->
                val declared = topology().services()
                val unknown = wanted - declared
                require(unknown.isEmpty()) {
                    "core '${name()}' is told to host $unknown, which its topology does not declare (declare the whole " +
                        "topology before start()); its services: ${declared.sorted()}"
                }
            }
            checkHostingModes()
        } catch (e: IllegalArgumentException) {
            notRunning += topology().services() // refused: nothing runs here, as serviceNames() then says
            throw e
        }
        warnOfUnknownQueueLimits()
        warnOfUnusedHostedChains()
        val hosted = (services.keys + coreThreadServices()).filter(::isHosted) + genericServices.keys
        try {
            withSession("declare the hosting modes of its services") { session ->
                sharedHosting.declare(session, hosted.filter { it in services.keys }, name())
            }
            claimHostLeases(hosted.filter { sharedHosting.modeOf(it) == Hosting.EXCLUSIVE })
        } catch (e: IllegalStateException) {
            notRunning += hosted
            throw e
        }
        services.values.forEach(::launchIfHosted)
        genericServices.values.forEach { loop -> launchHosted(loop.name()) { runInterruptible { runGenericLoop(loop) } } }
    }

    /**
     * The services of the topology that run on the core's own threads rather than as Redis
     * services: combinators of sources and timers. They get a host lease too, so one process at a
     * time runs each (they stop emitting when [isHostedHere] turns false).
     */
    private fun coreThreadServices(): List<String> = topology().nodes()
        .filter { it is TopologyNode.Combinator || it is TopologyNode.Timer }
        .map { it.name() }

    /**
     * A combinator or timer declared after [start] claims its host lease now, as [start] claims
     * those declared before it (waiting up to one lease time for another's to lapse), so a second
     * process that declares it too is refused and never emits it.
     *
     * @throws IllegalStateException if another live instance holds the lease ("already hosted by")
     */
    override fun hostOnCoreThreads(service: String) {
        if (!isHosted(service) || isClosed || service in hostLeases.services) return
        // refused: the declaration fails and is forgotten, nothing runs
        interruptibleInOutage({ "declaring '$service'" }, waitedFor = WAITED_FOR_REDIS_OR_LEASE, abortsWaitsForAnswers = true) {
            claimHostLeases(listOf(service), "'$service' declared after start()")
        }
        coreThreadClaims += service
    }

    /**
     * The declaration of combinator or timer [service] failed after [hostOnCoreThreads] claimed its
     * host lease: the lease is released, so that another process may host it (and this one again,
     * when the declaration is made again).
     */
    override fun unhostOnCoreThreads(service: String) {
        if (coreThreadClaims.remove(service)) hostLeases.release(listOf(service))
    }

    override fun onClose() {
        // close() from a service's or listener's own thread must not wait for that thread
        val ownThread = Thread.currentThread() in threads
        subscriptions.forEach { it.close() }
        subscriptions.clear()
        scope.cancel()
        // A generic service closing its own core was just interrupted by that cancel (it runs
        // interruptibly). That interrupt only says "the core is closing", which the caller knows:
        // cleared, it neither cuts this close's waits short nor reaches the code after close().
        if (ownThread) Thread.interrupted()
        // the clean-up's share of the close: on a Redis that does not answer it must not outlast shutdownTimeout
        val cleanupNanos = cleanupNanos(config().shutdownTimeout())
        val cleanupDeadline = System.nanoTime() + cleanupNanos
        val cleanup = try {
            val limit = Duration.ofNanos(cleanupNanos)
            endpoint.connect("prime-${name()}-cleanup", limit, limit)
        } catch (_: Exception) {
            null
        }
        connections.closeAll() // wakes every blocked read
        // A service's block that waits (a sleep, a queue's take, a call of another core's chain,
        // which waits on that core's connections) ends on its interrupt, at once, as on Liberty
        // and Radiant: with the connections closed nothing it returns could be stored now (the
        // value stays in its processing list for the next run), so waiting for it buys nothing.
        // Not the calling thread, nor a generic service's, which the cancel interrupted already.
        val current = Thread.currentThread()
        threads.forEach { if (it !== current && it !in inGenericLoops) it.interrupt() }
        cleanup?.use { jedis ->
            try {
                jedis.connection.setSoTimeout(ceilMillis(cleanupDeadline - System.nanoTime()).toInt())
                val pipeline = jedis.pipelined()
                for ((source, list) in readers) queueReaderRemoval(pipeline, keys, source, list)
                for (slot in 1..slotNumbers.get()) pipeline.del(replyKey(slot))
                hostLeases.releaseAll(pipeline)
                sharedHosting.releaseAll(pipeline)
                liveness.releaseAll(pipeline)
                pipeline.sync()
            } catch (e: Exception) {
                LOG.debug("core '{}' could not remove its readers and reply lists: {}", name(), e.toString())
            }
        }
        val timeout = config().shutdownTimeout()
        // A service closing its own core (a listener) cannot wait for itself: it waits for the
        // other services' threads only, in shutdownResources.
        if (!ownThread) {
            runBlocking { withTimeoutOrNull(boundedNanos(timeout) / 1_000_000) { supervisor.join() } }
                ?: LOG.warn("core '{}': services still running after {}", name(), timeout)
        }
        shutdownResources()
        readerMisses.flush() // the misses counted since the last line: no publish of this core comes after
        readerSkips.flush() // the skips counted since the last line: no read of this core comes after
    }

    /** Runs a generic service's [loop], its thread noted in [inGenericLoops] meanwhile. */
    private fun runGenericLoop(loop: GenericServiceLoop) {
        val current = Thread.currentThread()
        inGenericLoops += current
        try {
            loop.run()
        } finally {
            inGenericLoops -= current
        }
    }

    /** Also this core's own threads (services, listeners, the heartbeat), which a close under way joins. */
    protected override fun isOwnThread(thread: Thread): Boolean = super.isOwnThread(thread) || thread in threads

    /** Stops the threads (all but the calling one, which ends when its service returns) and the embedded Redis. */
    private fun shutdownResources() {
        val current = Thread.currentThread()
        var interrupted = false
        try {
            dispatcher.close()
            executor.shutdown()
            // every service but the calling one: a service closing its own core goes on until it returns
            threads.filter { it !== current }.forEach(Thread::interrupt)
            val deadline = System.nanoTime() + boundedNanos(config().shutdownTimeout())
            for (thread in threads) {
                if (thread === current) continue
                try {
                    thread.join(((deadline - System.nanoTime()) / 1_000_000).coerceAtLeast(1))
                } catch (_: InterruptedException) {
                    interrupted = true
                }
                if (thread.isAlive) LOG.warn("core '{}': thread {} still running after {}", name(), thread.name, config().shutdownTimeout())
            }
        } finally {
            embedded?.close()
            if (interrupted) current.interrupt()
        }
    }

    // ------------------------------------------------------------------ for the media's classes

    internal fun checkOpen() {
        ensureOpen()
    }

    /** Fails at once if [start] was not called, or failed: then no service of this process runs. */
    internal fun checkStarted(what: String) {
        ensureStartDidNotFail(what) // a failed start runs nothing: as before start(), refused
        check(isStarted || isClosed) { // a closed core fails where its use does: CoreClosedException
            "$what of core '${name()}' before start(): start() was not called; declare the topology, then call " +
                "core.start(), then call chains and read sources"
        }
    }


    /**
     * The codec's bytes of [value]: the one place every publish, call and service output is
     * encoded, so the size limit holds on every path. [held]: the caller's session of the codec, if
     * it keeps one across values ([holdCodec]).
     *
     * @throws ValueTooLargeException above [Builder.maxValueBytes]
     */
    internal fun encode(value: Any?, held: HeldCodecSession? = null): ByteArray? {
        if (value == null) return null
        val bytes = held?.encode(value, 0) ?: codec.encode(value)
        checkSize(value, bytes.size)
        return bytes
    }

    /**
     * A session of the core's codec for one user to keep across many values ([HeldCodecSession]),
     * or `null` if the codec is not a [KryoCodec] (its calls then go to the codec, value by value).
     */
    internal fun holdCodec(): HeldCodecSession? = kryoCodec?.let(::HeldCodecSession)

    /**
     * The envelope of [value] as a value with id 0 ([Envelope.withId] writes its id), under the same
     * size limit as [encode]. A [KryoCodec] encodes into the envelope itself (with [held], if the
     * caller keeps a session); another codec's bytes are copied into one.
     *
     * @throws ValueTooLargeException above [Builder.maxValueBytes]
     */
    internal fun valueEnvelope(value: Any?, held: HeldCodecSession? = null): ByteArray {
        val kryo = kryoCodec
        if (value == null || kryo == null) return Envelope.value(0L, encode(value))
        val encoded = held?.encode(value, Envelope.VALUE_ROOM) ?: kryo.encode(value, Envelope.VALUE_ROOM)
        checkSize(value, encoded.size - Envelope.VALUE_ROOM)
        return Envelope.valueAround(encoded)
    }

    private fun checkSize(value: Any, size: Int) {
        if (size > maxValueBytes) {
            throw ValueTooLargeException(
                "a ${value.javaClass.name} encodes to $size bytes, over this core's limit of $maxValueBytes " +
                    "bytes: send a reference instead (a file or object-store key), split the value, or raise " +
                    "OptimusCore.Builder.maxValueBytes (every process of the topology should agree)",
            )
        }
    }

    /**
     * The value in [length] bytes of [bytes] from [offset]: read in place by a [KryoCodec], copied
     * out for any other codec (whose `decode` takes a whole array). [held]: as for [encode].
     *
     * @throws CodecException if the codec cannot decode them
     */
    internal fun decode(bytes: ByteArray, offset: Int, length: Int, held: HeldCodecSession? = null): Any {
        return held?.decode(bytes, offset, length)
            ?: kryoCodec?.decode(bytes, offset, length)
            ?: codec.decode(bytes.copyOfRange(offset, offset + length))
    }

    /** The queue limit of [service] (`null`: not a service of this topology). */
    internal fun queueLimitOf(service: String?): Int = service?.let(queueLimits::get) ?: queueLimit

    /**
     * Binds [stages] for calls and returns the remote call to the first. A call to a user of an
     * isolated chain of this core also refuses a call from inside that chain ([SelfCalls]); which
     * calls are such is read from the topology at [start], or at once after it.
     */
    internal fun <I, O> bindForCalls(chainName: String, stages: List<StageSpec>): Block<I, O> {
        interruptibleInOutage({ "declaring chain '$chainName'" }, waitedFor = WAITED_FOR_REDIS_OR_LEASE, abortsWaitsForAnswers = true) {
            bind(chainName, stages, null, counted = false)
        }
        calledServices[chainName] = stages.map { it.name }
        val first = stages.first().name
        val call = RemoteCall<I, O>(this, chainName, first, stages.mapTo(LinkedHashSet()) { it.name }, keys.serviceInput(first))
        unresolvedCalls += call
        if (isStarted) resolveSelfCalls() // else start() does
        return call
    }

    /**
     * Takes back the services [bindForCalls] bound for chain [chainName], whose block was made for
     * a part of a declaration that then failed (a template whose other part was refused): cancels
     * their runs ([stopRun]) and waits for them, at most the shutdown timeout, releases their host leases and
     * forgets them, so the chain, left unused, can be declared again. `false` if a run still runs
     * a block then: its services stay bound (a second run beside it would go on under the same
     * instance), and the chain stays consumed. `true` if nothing was bound for it.
     */
    internal fun unbindForCalls(chainName: String): Boolean {
        val names = calledServices[chainName] ?: return true
        if (takeBack(names, claimed = names.filter { it in hostLeases.services })) {
            LOG.warn(
                "core '{}': a declaration that took chain '{}' failed, and a service of it (of {}) was still running a " +
                    "block {} after it was stopped: its services stay bound, and the chain cannot be declared again",
                name(), chainName, names, config().shutdownTimeout(),
            )
            return false
        }
        calledServices.remove(chainName)
        notRunning -= names.toSet()
        return true
    }

    /**
     * Gives each remote call made since the last time whose first service is a user of an isolated
     * chain the [SelfCalls] of that chain's services in this core ([servicesRunFor]). An isolated
     * chain of another core (its block is that core's) has none here.
     */
    private fun resolveSelfCalls() {
        if (unresolvedCalls.isEmpty()) return
        val topology = topology()
        while (true) {
            val call = unresolvedCalls.poll() ?: return
            val user = topology.node(call.firstService).orElse(null) as? TopologyNode.IsolatedUser ?: continue
            val services = LinkedHashSet<String>().also { servicesRunFor(user.shared(), topology, it) }
            if (services.isNotEmpty()) call.selfCalls = SelfCalls(this, user.shared(), services)
        }
    }

    /**
     * Adds to [into] the services that run only for chain [node] when it is called: its own (each
     * chain of a linked chain), and those of the chains it consumed and calls (a template's parts,
     * a repeater's chain), down to the blocks. Not another isolated chain's (its users' calls come
     * from anywhere), nor a source's.
     */
    private fun servicesRunFor(node: String, topology: Topology, into: MutableSet<String>) {
        forEachNodeRunFor(node, topology) { name, _ -> calledServices[name]?.let(into::addAll) }
    }

    /**
     * Gives [visit] each node that runs when chain [shared] is called, once, from [shared] down:
     * the chain, each chain of a linked chain, the chains it runs (a template's parts, a repeater's
     * chain), down to the blocks, with its topology node (`null` if the topology lacks it). A user
     * of another isolated chain is visited but not walked into (its users' calls come from
     * anywhere). Walked without recursion, for a linked chain of any length.
     */
    private inline fun forEachNodeRunFor(shared: String, topology: Topology, visit: (String, TopologyNode?) -> Unit) {
        val seen = HashSet<String>()
        val next = ArrayDeque<String>().apply { add(shared) }
        while (next.isNotEmpty()) {
            val name = next.removeLast()
            if (!seen.add(name)) continue
            val node = topology.node(name).orElse(null)
            visit(name, node)
            if (node == null || !node.isChain() || node is TopologyNode.IsolatedUser) continue
            for (part in node.parts().asReversed()) next.addLast(part.node())
        }
    }

    /** Records a reader the program opened on [source] in the topology. */
    internal fun recordReader(source: OptimusSource<*>) {
        recordReader(source.name())
    }

    /**
     * A new reader of [source], its list recorded as this instance's and registered with the
     * source; it waits for Redis in an outage, and an interrupt there fails it as
     * [interruptibleInOutage] says (a list recorded by then goes with the core's close).
     */
    internal fun <T> newReader(source: OptimusSource<T>): Reader<T> {
        checkOpen()
        val list = keys.reader(UUID.randomUUID().toString())
        interruptibleInOutage(
            { "opening a reader of source '${source.name()}'" },
            "; no reader was opened",
            WAITED_FOR_ANSWER,
            abortsWaitsForAnswers = true,
            flagSetBeforeEnds = false,
        ) {
            withSession("register a reader of source '${source.name()}'") { liveness.own(it, list, source.keys.readers) }
            readers += source.keys to list
            register(source.keys, list)
        }
        return OptimusReader(this, source.keys, list)
    }

    /** A closed reader: the core's close need not remove its lists. */
    internal fun forgetReader(list: ByteArray) {
        readers.removeIf { it.second === list }
    }

    /** Queues the removal of a closed reader's list from this instance's ownership records. */
    internal fun disownReader(pipeline: Pipeline, list: ByteArray) {
        liveness.disown(pipeline, list)
    }

    /**
     * Runs [op], a step of a call to chain [chainName] that may wait between two attempts to reach
     * Redis (an outage), as [interruptibleInOutage]: interrupted there on an open core, the call
     * fails with a [dev.prime.PrimeException] that says so, as a wait for the reply does, the flag
     * kept, and whether its request may have reached the service ([sent]: the step may have sent it).
     */
    internal inline fun <T> reachingRedisFor(chainName: String, sent: Boolean, op: () -> T): T =
        interruptibleInOutage(
            { "the call to chain '$chainName'" },
            if (sent) "; its request may have reached the service" else "; its request was not sent",
            op = op,
        )

    /**
     * Runs [op], which may wait between two attempts to reach Redis (an outage) on the caller's
     * thread. That wait ends with [CoreClosedException] when the thread's interrupt flag is set: on
     * an open core, [op] fails instead with a [dev.prime.PrimeException] saying that [what] was
     * interrupted while it waited [waitedFor] (then [outcome]), the flag kept. With
     * [abortsWaitsForAnswers] an interrupt that comes while [op] waits for Redis's answer ends that
     * wait too, at once, the same way ([RedisSession.ABORTS_ON_INTERRUPT]): a frozen Redis answers
     * never, and the socket would wait out its timeout. With [flagSetBeforeEnds] as well (a
     * declaration, a start) a flag already set ends each of its Redis operations before it is sent;
     * without it (a publish, a read) such an operation is sent, and succeeds if Redis answers.
     */
    internal inline fun <T> interruptibleInOutage(
        what: () -> String,
        outcome: String = "",
        waitedFor: String = "to reach Redis again",
        abortsWaitsForAnswers: Boolean = false,
        flagSetBeforeEnds: Boolean = abortsWaitsForAnswers,
        op: () -> T,
    ): T {
        // set as it begins: with flagSetBeforeEnds, it ends before anything is sent, and never waited
        val refusedAtOnce = flagSetBeforeEnds && Thread.currentThread().isInterrupted
        return try {
            if (abortsWaitsForAnswers) {
                val outer = RedisSession.ABORTS_ON_INTERRUPT.get()
                RedisSession.ABORTS_ON_INTERRUPT.set(flagSetBeforeEnds)
                try {
                    op()
                } finally {
                    RedisSession.ABORTS_ON_INTERRUPT.set(outer)
                }
            } else {
                op()
            }
        } catch (e: CoreClosedException) {
            if (connections.isClosed || !Thread.currentThread().isInterrupted) throw e
            val why = if (refusedAtOnce) {
                "was refused at once: its thread had been interrupted before it began (the interrupt flag was already " +
                    "set as it began), so it neither asked Redis anything nor waited $waitedFor; clear the flag, or find who " +
                    "set it, and make it again"
            } else {
                "was interrupted while it waited $waitedFor"
            }
            throw dev.prime.PrimeException("${what()} $why$outcome (the thread's interrupt flag is kept)").apply { initCause(e) }
        }
    }

    /**
     * An idle caller slot, or a new one, whose reply list is recorded by [deadline] (a call's; a
     * [System.nanoTime], `null`: no limit), else [RedisUnavailableException] naming the call to
     * [chainName].
     */
    internal fun borrowSlot(deadline: Long?, chainName: String): CallerSlot = idleSlots.poll() ?: newSlot(deadline, chainName)

    private fun newSlot(deadline: Long?, chainName: String): CallerSlot {
        val reply = replyKey(slotNumbers.incrementAndGet())
        withSession("record a reply list") { liveness.own(it, reply, null, deadline, "the call to service '$chainName'") }
        return CallerSlot(this, reply).also { allSlots += it }
    }

    internal fun returnSlot(slot: CallerSlot) {
        if (isClosed) slot.close() else idleSlots += slot
    }

    /**
     * Keeps what a request's block threw for a caller in this process: a [ChainFailedException],
     * or the block's own [CoreClosedException] or [VirtualMachineError], which reach the caller
     * unwrapped as on the media that run blocks on the caller's thread.
     */
    internal fun rememberFailure(id: Long, failure: Throwable) {
        failures[id] = failure
    }

    internal fun takeFailure(id: Long): Throwable? = failures.remove(id)

    /**
     * Gives a failure to the error handler as the user knows it: a [ChainFailedException] (a chain
     * called from this service failed) under the failing chain's name, with its block's own
     * throwable. A handler that throws is logged as on every media ([FailureReport]).
     */
    internal fun reportFailure(service: String, input: Any, error: Throwable) {
        FailureReport.report(config().errorHandler(), service, input, error)
    }

    // ------------------------------------------------------------------ internals

    private fun replyKey(slot: Int) = keys.reply("$instance:$slot")

    private fun bindToSource(chain: String, source: OptimusSource<*>, stages: List<StageSpec>, output: OptimusSource<*>?) {
        val input = keys.serviceInput(stages.first().name)
        beginLiveness()
        // added before it is registered (see Redeclaration), taken back if the link fails: a
        // re-declaration must not register an input that no service reads
        val binding = source.keys to input
        declarations.bindings += binding
        try {
            register(source.keys, input, service = true)
            bind(chain, stages, output?.keys, counted = true)
        } catch (e: Throwable) {
            declarations.bindings -= binding
            throw e
        }
    }

    /**
     * Binds the services of chain [chain] and, once the core started, launches those hosted here.
     * [counted]: the stages are fed by a source, so values reach their queues and are counted; else
     * only calls do. On a started core it first claims the host leases of all of them that have
     * one host at a time, so that one held by another process fails the binding before any runs.
     * A binding that fails leaves nothing behind ([unbind]), so the declaration can be made again.
     */
    private fun bind(chain: String, stages: List<StageSpec>, output: SourceKeys?, counted: Boolean) {
        val names = stages.map { it.name }
        val leasesBefore = hostLeases.services
        val notRunningBefore = names.filterTo(HashSet()) { it in notRunning }
        val bound = ArrayList<String>(stages.size)
        try {
            if (isStarted && !isClosed) {
                claimHostLeases(
                    names.filter { isHosted(it) && it !in launched && it !in leasesBefore && sharedHosting.modeOf(it) == Hosting.EXCLUSIVE },
                    "chain '$chain' declared after start()",
                    ofAChain = true,
                )
            }
            stages.forEachIndexed { index, stage ->
                val last = index == stages.size - 1
                val service = StageService(
                    stage.name,
                    this,
                    stage.logic,
                    if (last) null else keys.serviceInput(stages[index + 1].name),
                    if (last) output else null,
                    counted,
                )
                check(services.putIfAbsent(stage.name, service) == null) { "service '${stage.name}' is bound twice" }
                bound += stage.name
                if (isStarted) launchIfHosted(service)
            }
        } catch (e: Throwable) {
            unbind(chain, names, bound, leasesBefore, notRunningBefore, e)
            throw e
        }
    }

    /**
     * Takes back a binding of chain [chain] that failed ([failure]): cancels the runs it launched of
     * [bound] (the stages it bound; [stopRun]) and waits for them to end, at most the shutdown timeout, then
     * forgets them, gives up the host leases it claimed for [names] and what it marked not running.
     * A run that does not end in time still runs a block: then the services stay bound and the
     * failure is a [dev.prime.ChainAlreadyUsedException] saying that the chain cannot be declared again.
     */
    private fun unbind(
        chain: String,
        names: List<String>,
        bound: List<String>,
        leasesBefore: Set<String>,
        notRunningBefore: Set<String>,
        failure: Throwable,
    ) {
        if (takeBack(bound, claimed = names.filter { it in hostLeases.services && it !in leasesBefore })) {
            throw dev.prime.ChainAlreadyUsedException(
                chain,
                "a service it had started here (of $bound) was still running a block ${config().shutdownTimeout()} after " +
                    "it was stopped, so its services stay bound (${failure.message})",
                failure,
            )
        }
        notRunning -= names.filterNot { it in notRunningBefore }.toSet()
    }

    /**
     * Takes back services [bound] by a declaration that failed: stops their runs ([stopRun]) and
     * waits for them, at most the shutdown timeout, gives up the host leases [claimed] for them (a
     * run still in its block then stores nothing: its steps are fenced) and, unless a run still
     * runs a block, forgets them. Whether one still does (then they stay bound).
     */
    private fun takeBack(bound: Collection<String>, claimed: Collection<String>): Boolean {
        val runs = bound.mapNotNull(::stopRun)
        val stillRunning = awaitEnded(runs, boundedNanos(config().shutdownTimeout()))
        hostLeases.release(claimed)
        if (!stillRunning) {
            for (name in bound) {
                services.remove(name)
                launched -= name
            }
        }
        return stillRunning
    }

    /**
     * Cancels the run of [service] launched here, if any, for a declaration that failed, and wakes
     * it from a wait for input in Redis, which a cancellation does not end ([StageService.wake]):
     * an idle run then ends at once, and only a run still in a block outlasts the shutdown timeout.
     * Returns the run, to wait for.
     */
    private fun stopRun(service: String): Job? = hostedJobs.remove(service)?.also {
        it.cancel()
        services[service]?.wake()
    }

    /**
     * Waits until every one of [runs] has ended, at most [nanos], without giving up on an interrupt
     * (kept for the caller); whether one still runs.
     */
    private fun awaitEnded(runs: List<Job>, nanos: Long): Boolean {
        if (runs.isEmpty()) return false
        val ended = java.util.concurrent.CountDownLatch(runs.size)
        runs.forEach { it.invokeOnCompletion { ended.countDown() } }
        val deadline = System.nanoTime() + nanos
        var interrupted = false
        try {
            while (true) {
                try {
                    return !ended.await((deadline - System.nanoTime()).coerceAtLeast(0), java.util.concurrent.TimeUnit.NANOSECONDS)
                } catch (_: InterruptedException) {
                    interrupted = true
                }
            }
        } finally {
            if (interrupted) Thread.currentThread().interrupt()
        }
    }

    private fun isHosted(service: String) = hosts == null || service in hosts

    private fun launchIfHosted(service: StageService) = launchHosted(service.name) { service.run() }

    /** Runs [body] as hosted service [name] once, if this process hosts it, holding its host lease. */
    private fun launchHosted(name: String, body: suspend () -> Unit) {
        if (!isHosted(name) || !launched.add(name) || isClosed) return
        val mode = sharedHosting.modeOf(name)
        if (mode != Hosting.EXCLUSIVE) {
            launchShared(name, mode, body)
            return
        }
        if (name !in hostLeases.services) {
            try {
                claimHostLeases(listOf(name), "service '$name' declared after start()")
            } catch (e: RuntimeException) {
                launched -= name
                if (e is IllegalStateException) notRunning += name
                throw e
            }
        }
        hostedJobs[name] = scope.launch(CoroutineName(name)) { body() }
    }

    /** Registers this process's liveness lease and starts its heartbeat, once. */
    private fun beginLiveness() {
        withSession("register this process's liveness lease") { liveness.begin() }
    }

    /**
     * Claims the host leases of [services] (waiting up to one lease time for others' to lapse), for
     * start(), or for [declaration] made after it (its refusal then names it, and says that the same
     * chain can be declared again if [ofAChain]).
     */
    private fun claimHostLeases(services: List<String>, declaration: String? = null, ofAChain: Boolean = false) {
        withSession("claim the host leases of $services") { hostLeases.claim(services, name(), declaration, ofAChain) }
    }

    /** The fence [service]'s steps check: its host lease must hold this instance's id. */
    internal fun hostFence(service: String): HostFence =
        HostFence(keys.hostLease(service), instance.toByteArray(UTF_8), leaseTime.toMillis().toString().toByteArray(UTF_8))

    /**
     * Where a service with one host at a time keeps what it took: its own processing list, fenced by its host lease.
     * Its blocking take waits in Redis at most a third of the lease time (as an unordered seat's does): a take sent
     * before this host froze then ends before its lease can lapse, so it cannot move a value into the list after a
     * successor took the service over (the successor's step would acknowledge that value unprocessed).
     */
    internal fun soleSeat(service: String): HostSeat =
        HostSeat(
            service, keys.serviceProcessing(service), hostFence(service), shared = false,
            minOf(RedisConnections.POLL_SECONDS, leaseTime.toMillis() / 3 / 1000.0),
        )

    /**
     * Refuses hosting modes for services the topology lacks, for chains nothing used by start() (their
     * services do not run), or for services that are not chains', and
     * [Hosting.UNORDERED] for the services that run for an isolated chain ([refuseUnorderedIsolatedChains]).
     */
    private fun checkHostingModes() {
        val moded = sharedHosting.nonDefault
        val unknown = moded - topology().services()
        require(unknown.isEmpty()) {
            "core '${name()}' is given hosting modes for $unknown, which its topology does not declare; its services: " +
                "${topology().services().sorted()}"
        }
        val notRunning = moded - services.keys
        val topology = topology()
        val (unusedChains, notChains) = notRunning.partition { topology.node(it).map { node -> node.isChain() }.orElse(false) }
        require(unusedChains.isEmpty()) {
            "core '${name()}' is given a hosting mode for ${unusedChains.joinToString { "chain '$it' (Hosting.${sharedHosting.modeOf(it)})" }}, " +
                "which no chain of this process has used by start() (toBlock(), a link, a template or a source's then()): " +
                "a chain's service runs only once the chain is used, so its mode cannot be agreed with its other hosts. " +
                "Use the chain before start(), as the other processes of the topology do (the toBlock() calls too), or " +
                "remove hosting(...) for it from this process's builder"
        }
        require(notChains.isEmpty()) {
            "core '${name()}' is given Hosting.ORDERED or UNORDERED for $notChains: those are combinators, timers or generic " +
                "services, which have one host at a time (Hosting.EXCLUSIVE); hosting modes apply to the services of chains"
        }
        refuseUnorderedIsolatedChains(topology().nodes().filterIsInstance<TopologyNode.IsolatedUser>())
    }

    /**
     * Refuses [Hosting.UNORDERED] for a service that runs for the isolated chain of one of [users]
     * ([isolatedServices]): its competing hosts would each take a call at once, and `isolate()`
     * promises the shared chain never runs for two calls at once. Read from the topology, so a
     * process that hosts the isolated chain and none of its users refuses it too.
     *
     * @throws IllegalArgumentException naming the service, the isolated chain and the fix
     */
    private fun refuseUnorderedIsolatedChains(users: List<TopologyNode.IsolatedUser>) {
        val unordered = sharedHosting.nonDefault.filterTo(HashSet()) { sharedHosting.modeOf(it) == Hosting.UNORDERED }
        if (unordered.isEmpty() || users.isEmpty()) return
        val topology = topology()
        for (shared in users.mapTo(LinkedHashSet()) { it.shared() }) {
            val service = isolatedServices(shared, topology).firstOrNull { it in unordered } ?: continue
            throw IllegalArgumentException(
                "core '${name()}' is given Hosting.UNORDERED for service '$service', which runs for isolated chain " +
                    "'$shared' (core.isolate(...)): its hosts would each take a call at once, and an isolated chain never " +
                    "runs for two calls at once. Give '$service' Hosting.EXCLUSIVE (the default: one host) or " +
                    "Hosting.ORDERED (one active host, others standing by) in every process that hosts it",
            )
        }
    }

    /**
     * A user of an isolated chain declared after [start]: refused as [start] refuses those declared
     * before it ([refuseUnorderedIsolatedChains]), so the declaration fails and leaves nothing.
     */
    internal fun checkIsolatedUser(chain: String) {
        if (!isStarted || sharedHosting.nonDefault.isEmpty()) return // start() checks those declared before it
        val user = topology().node(chain).orElse(null) as? TopologyNode.IsolatedUser ?: return
        refuseUnorderedIsolatedChains(listOf(user))
    }

    /**
     * The services that run only for isolated chain [shared], read from the topology: the chain's
     * own (a chain of a block, a template, another core's chain), each chain of a linked chain, and
     * those of the chains it runs (a template's parts, a repeater's chain), down to the blocks; a
     * user of another isolated chain is one, but not that chain's (its users guard it)
     * ([forEachNodeRunFor]).
     */
    private fun isolatedServices(shared: String, topology: Topology): Set<String> {
        val found = LinkedHashSet<String>()
        forEachNodeRunFor(shared, topology) { _, node ->
            if (node != null && node.isChain() && node.isService()) found += node.name()
        }
        return found
    }

    /**
     * Warns of queue limits given for services that are not (yet) services of this core's chains: a
     * misspelt name would otherwise be ignored without a word. Not refused, as unknown hosts are:
     * a service declared after [start] may be the one the limit is for.
     */
    private fun warnOfUnknownQueueLimits() {
        val unknown = queueLimits.keys - services.keys
        if (unknown.isEmpty()) return
        LOG.warn(
            "core '{}' is given queue limits for {}, which are not services of its chains (yet): a limit applies only to " +
                "a service of that name declared later; its services: {}",
            name(), unknown.sorted(), services.keys.sorted(),
        )
    }

    /**
     * A chain's service runs once the chain is used in this process ([Chain.toBlock], a link, a
     * template, a source's `then`): a chain [Builder.hosts] names that nothing here has used by
     * start runs nowhere, and other processes' calls to it wait out their timeout. One WARN names them.
     */
    private fun warnOfUnusedHostedChains() {
        val wanted = hosts ?: return
        val unused = wanted - services.keys - genericServices.keys - coreThreadServices().toSet()
        if (unused.isEmpty()) return
        LOG.warn(
            "core '{}' is told to host {}, but no chain of this process has used {} by start() (toBlock(), a link, " +
                "a template or a source's then()): a chain's service runs only once the chain is used, so calls " +
                "from other processes wait out their timeout; declare the topology as the other processes do, " +
                "the toBlock() calls too",
            name(), unused.sorted(), if (unused.size == 1) "it" else "them",
        )
    }

    /**
     * Launches [name], an [Hosting.ORDERED] or [Hosting.UNORDERED] service: unordered, a run in a
     * seat of its own next to the other hosts; ordered, at once if its host lease is free, else as
     * a standby that takes over when the lease lapses or is released.
     */
    private fun launchShared(name: String, mode: Hosting, body: suspend () -> Unit) {
        val service = services.getValue(name)
        try {
            withSession("declare the hosting of service '$name'") { session ->
                if (!sharedHosting.isDeclared(name)) sharedHosting.declare(session, listOf(name), name())
                if (mode == Hosting.UNORDERED) {
                    launchSeated(session, service)
                } else {
                    val refused = session.retrying { hostLeases.tryClaim(it, listOf(name)) }
                    if (refused.isEmpty()) {
                        hostedJobs[name] = scope.launch(CoroutineName(name)) { body() }
                    } else {
                        notRunning += name
                        standBy(name, body, refused.getValue(name))
                    }
                }
            }
        } catch (e: RuntimeException) {
            launched -= name
            if (e is IllegalStateException) notRunning += name
            throw e
        }
    }

    /** Starts a run of unordered [service] in a new seat (a new token: an earlier run of it here stores nothing more). */
    private fun launchSeated(session: RedisSession, service: StageService) {
        val run = service.seatedAt(sharedHosting.claim(session, service.name, service.counted))
        notRunning -= service.name
        hostedJobs[service.name] = scope.launch(CoroutineName(service.name)) { run.run() }
    }

    /**
     * Stands by for ordered service [name]: claims its host lease when the holder's lapses (first
     * after [remaining] ms) or within a third of the lease time after it is released, then runs
     * [body]. Not hosted here ([isHostedHere]) until then. With [earlier], the cancelled run of
     * the service here, it claims nothing until that run has ended: a run still in its block or in
     * a blocking Redis call would otherwise go on beside the new one, under the same instance id,
     * which the fence lets through, and with the same service's state.
     */
    private fun standBy(name: String, body: suspend () -> Unit, remaining: Long, earlier: Job? = null) {
        LOG.info("core '{}' stands by for service '{}': another process hosts it (Hosting.ORDERED)", name(), name)
        val third = (leaseTime.toMillis() / 3).coerceAtLeast(1)
        hostedJobs[name] = scope.launch(CoroutineName("$name standby")) {
            if (earlier != null && !earlier.isCompleted) {
                LOG.info(
                    "core '{}': service '{}' stands by once its stopped run has ended (its block or a Redis call still runs)",
                    name(), name,
                )
                earlier.join()
            }
            var wait = remaining
            while (true) {
                delay((wait + 1).coerceIn(STANDBY_MIN_WAIT_MS, third))
                if (isClosed) return@launch
                wait = try {
                    withSession("claim the host lease of service '$name'") { session ->
                        session.once { hostLeases.tryClaim(it, listOf(name)) }
                    }[name] ?: break
                } catch (e: CancellationException) {
                    throw e
                } catch (e: Exception) {
                    if (isClosed) return@launch
                    LOG.debug("core '{}': the standby of service '{}' could not reach Redis: {}", name(), name, e.toString())
                    third
                }
            }
            notRunning -= name
            LOG.info("core '{}' takes over service '{}' (it stood by)", name(), name)
            body()
        }
    }

    /** The heartbeat's part for shared hosting: renews modes and seats; a lapsed seat's service starts a new run. */
    private fun renewSharedHosting(session: RedisSession) {
        for (service in session.once(sharedHosting::renew)) {
            if (isClosed) return
            LOG.warn(
                "core '{}': its seat of service '{}' lapsed (this process was frozen or cut off from Redis longer than the " +
                    "lease time, or Redis lost it): what it had taken and not stored may be back in the input for other " +
                    "hosts; the service starts a new run",
                name(), service,
            )
            val old = hostedJobs.remove(service)
            old?.cancel()
            scope.launch(CoroutineName("$service reseat")) {
                try {
                    // the old run may still be in a blocking take into this host's list (a Jedis call, which
                    // cancel() does not end): the new run starts once it ended, so its first peek sees what that
                    // take moved instead of acknowledging it unprocessed
                    withTimeoutOrNull(leaseTime.toMillis()) { old?.join() }
                    withSession("take a seat of service '$service'") { launchSeated(it, services.getValue(service)) }
                } catch (e: Exception) {
                    if (!isClosed) LOG.error("core '{}' could not start service '{}' again: {}", name(), service, e.toString())
                }
            }
        }
    }

    /**
     * Called by [service]'s own loop when a step found its host lease held by [holder]: stops the
     * service as the heartbeat would have (whichever sees it first stops it, once).
     */
    internal fun hostingLost(session: RedisSession, seat: HostSeat, holder: String) {
        // a shared seat's lease is written by this instance only: a newer run of the service holds it, which goes on
        if (seat.shared) return
        if (hostLeases.drop(seat.service)) stopLostService(seat.service, hostLeases.describe(session, holder))
    }

    /** Stops [service], whose host lease [holder] holds now (this process was frozen or cut off longer than the lease). */
    private fun stopLostService(service: String, holder: String) {
        notRunning += service
        val job = hostedJobs.remove(service)
        job?.cancel()
        val ordered = sharedHosting.modeOf(service) == Hosting.ORDERED
        val message = "core '${name()}' stops service '$service': its host lease is now held by $holder (this process " +
            "was frozen or cut off from Redis longer than the lease time, and another took over). " +
            if (ordered) "It stands by to take the service over again (Hosting.ORDERED)" else
                "Restart this process to host it again once the other stops"
        if (ordered && !isClosed) standBy(service, { services.getValue(service).run() }, 0, earlier = job)
        LOG.warn(message)
        reportFailure(service, holder, IllegalStateException(message))
        job?.invokeOnCompletion {
            LOG.warn("core '{}' stopped service '{}' (its host lease is held by {})", name(), service, holder)
        }
    }

    /** Adds [list] to [source]'s plain readers, or to its service inputs if it is a [service]'s (a queue). */
    private fun register(source: SourceKeys, list: ByteArray, service: Boolean = false) {
        withSession("register a reader of source '${source.name}'") { session ->
            session.retrying { registerOnce(it, source, list, service) }
            liveness.declared(session)
        }
    }

    private fun registerOnce(jedis: Jedis, source: SourceKeys, list: ByteArray, service: Boolean) {
        Script.REGISTER.run(
            jedis,
            listOf(if (service) source.services else source.readers, source.log, list, if (service) keys.queuedOf(list) else keys.missedOf(list)),
            listOf((if (service) "1" else "0").toByteArray(UTF_8)),
        )
    }

    /**
     * Publishes [envelopes] to [source] in one atomic step, all or nothing. While a service queue
     * the source feeds has no room, or Redis is unreachable, it waits, up to the publish timeout.
     */
    private fun publish(source: SourceKeys, envelopes: List<ByteArray>) {
        checkStarted("publishing to an Optimus source")
        val deadline = System.nanoTime() + boundedNanos(publishTimeout)
        val what = "publish to source '${source.name}'"
        val step = StepBatch(source.log, source.log, source, null, null, null, stepRules)
        envelopes.forEach(step::publish)
        withSession(what) { session ->
            var backoff: Backoff? = null
            while (true) {
                // interrupted between two attempts on an open core: not a close, and never a silent
                // loss (an event source drops what a close ends)
                val result = interruptibleInOutage(
                    { what },
                    "; it may not have been published (an attempt whose answer was lost may have stored it)",
                    WAITED_FOR_ANSWER,
                    abortsWaitsForAnswers = true,
                    flagSetBeforeEnds = false,
                ) {
                    session.retryingUntil(deadline, what) { jedis ->
                        if (source.view == null) source.refreshView(jedis, keys)
                        step.execute(jedis, ack = 0, take = 0, strict = true)
                    }
                }
                when (result) {
                    is StepResult.Stored -> return@withSession readerMisses.record(source, result.view, result.missed)
                    is StepResult.Stale -> source.view = null
                    is StepResult.Fenced, StepResult.Stray -> throw IllegalStateException("a publish step (no fence) was answered $result")
                    is StepResult.Full -> {
                        val left = deadline - System.nanoTime()
                        if (left <= 0 || envelopes.size > result.limit) throw queueFull(source, result, envelopes.size)
                        if (Thread.currentThread().isInterrupted) throw interruptedPublish(what)
                        val wait = (backoff ?: Backoff().also { backoff = it }).next()
                        try {
                            connections.pauseInterruptibly(minOf(wait, (left + 999_999) / 1_000_000))
                        } catch (_: InterruptedException) {
                            Thread.currentThread().interrupt()
                            throw interruptedPublish(what)
                        }
                    }
                }
            }
        }
    }

    /**
     * A publish that met its thread's interrupt flag while it waited for room in a service's queue:
     * nothing was published. (Interrupted while it waited to reach Redis, it fails through
     * [interruptibleInOutage]: all of it may have been published then, once, as its ids skip a repeat.)
     */
    private fun interruptedPublish(what: String) = dev.prime.PrimeException(
        "$what was interrupted while it waited for room in a service's queue; nothing was published " +
            "(the thread's interrupt flag is kept)",
    )

    private fun queueFull(source: SourceKeys, full: StepResult.Full, count: Int): QueueFullException {
        val service = keys.serviceOf(full.key) ?: full.key.toString(UTF_8)
        val limit = full.limit.toInt()
        val why = if (count > limit) {
            "$count values in one publish are more than its queue limit of $limit"
        } else {
            "its queue holds ${full.length} values of its limit of $limit and no room came within $publishTimeout"
        }
        return QueueFullException(
            service,
            limit,
            "publish to source '${source.name}' refused, nothing was published: service '$service' is fed by it and $why. " +
                "Is a process that hosts '$service' running and keeping up? Raise the limit with " +
                "OptimusCore.Builder.queueLimit(\"$service\", n), or the wait with publishTimeout.",
        )
    }

    /**
     * Runs [action] (a call or a read); a Redis ACL refusal it meets becomes a
     * [dev.prime.PrimeException] saying what to grant, and a Redis out of memory one saying so:
     * what Redis refused changed nothing (a value to read stays for the next read).
     */
    internal inline fun <T> explainingRefusals(what: String, action: () -> T): T = try {
        action()
    } catch (e: JedisDataException) {
        if (RedisPermissions.isRefusal(e)) throw RedisPermissions.explain(e, redisUser, name(), what)
        if (isOutOfMemory(e)) throw outOfMemory(what, "nothing changed", e)
        throw e
    }

    /** Whether Redis refused a write because its maxmemory is reached (`noeviction`). */
    internal fun isOutOfMemory(e: JedisDataException): Boolean = e.message?.startsWith("OOM") == true

    /** The exception for [what] refused by a Redis out of memory, saying [outcome]. */
    internal fun outOfMemory(what: String, outcome: String, e: JedisDataException): dev.prime.PrimeException =
        dev.prime.PrimeException(
            "$what refused, $outcome: Redis is out of memory (its maxmemory is reached; free memory or raise " +
                "maxmemory). Redis said: ${e.message}",
            e,
        )

    /** Runs [action] on a pooled session; an ACL refusal becomes a [dev.prime.PrimeException] saying what to grant. */
    internal fun <T> withSession(what: String = "a Redis command", action: (RedisSession) -> T): T {
        val session = publishers.poll() ?: RedisSession(connections)
        try {
            return action(session)
        } catch (e: JedisDataException) {
            if (RedisPermissions.isRefusal(e)) throw RedisPermissions.explain(e, redisUser, name(), what)
            if (isOutOfMemory(e)) throw outOfMemory(what, "nothing was stored", e)
            throw e
        } finally {
            publishers += session
        }
    }

    private fun checkCodecAgreement() {
        val mine = codec.fingerprint()
        val theirs = withSession { session ->
            session.retrying { jedis ->
                jedis.set(keys.codec, mine.toByteArray(UTF_8), SetParams().nx())
                jedis.get(keys.codec)?.toString(UTF_8)
            }
        }
        check(theirs == null || theirs == mine) {
            "core '${name()}' uses a codec with fingerprint $mine, but this topology's processes use $theirs: allow " +
                "the same types (classes, sealed types, packages) in every process's KryoCodec (or delete the Redis key " +
                "'${keys.codec.toString(UTF_8)}' if the types changed on purpose)"
        }
    }

    /** A service's logic that runs [block] on each input and emits its output. */
    internal fun chainLogic(block: Block<*, *>) = StageLogic { input, emit ->
        @Suppress("UNCHECKED_CAST")
        emit((block as Block<Any?, Any?>).process(input))
    }

    /** Settings of an [OptimusCore]; [build] makes the core. */
    public class Builder internal constructor() {
        private var config: CoreConfig = CoreConfig.defaults()
        private var settings = Settings()

        /** The settings every media shares (name, retention, error handler, shutdown timeout). */
        public fun config(config: CoreConfig): Builder = apply { this.config = config }

        /**
         * Uses the Redis at [url] instead of starting an embedded one:
         * `redis://[user[:password]@]host[:port][/database]` (`rediss://` for TLS) for one server,
         * or `redis-cluster://[user[:password]@]host:port[,host:port...]` (`rediss-cluster://` for
         * TLS) for a Redis Cluster.
         *
         * On a cluster the listed nodes are seeds (any one that answers is enough; list several).
         * Every key of a topology carries the core name as its hash tag (`prime:{name}:...`), so a
         * topology lives in one hash slot, on one master, and the cores of many topologies (one
         * per core name, e.g. one per robot) spread over the masters. Each connection goes to the
         * master of the topology's slot, found by asking the cluster (`CLUSTER SLOTS`); after a failover
         * or a slot move (a refused connection, `MOVED`, `CLUSTERDOWN`, ...) the core looks the
         * master up again and carries on, waiting as in an outage until the cluster has one. A
         * cluster has database 0 only; the user and password (ACL, or `AUTH` with `requirepass`)
         * and TLS (the JVM's trust store, full host-name verification: the nodes must announce
         * names or addresses their certificates hold) apply to every node. Redis replicates
         * asynchronously: to lose nothing a master acknowledged when it fails over, add
         * [replicaAcks].
         *
         * @throws IllegalArgumentException if the URL is malformed; the message says how to fix it
         */
        public fun redis(url: String): Builder = apply {
            if (RedisClusterEndpoint.isClusterUrl(url)) RedisClusterEndpoint.parse(url) else RedisEndpoint.parse(url)
            settings = settings.copy(redisUrl = url)
        }

        /**
         * Makes every Redis operation of the core wait until [replicas] replicas of the master
         * have it (Redis `WAIT`, up to [timeout], default 1 s, at most 5 s), so that a failover
         * to a replica (Redis Cluster, Sentinel, a managed service) loses nothing the core was
         * told is stored: a publish returns, a service acknowledges its input, a reader hands out
         * a value only once a replica has it. An operation that too few replicas confirm in time
         * counts as failed on a broken connection and is retried: its effects may be stored
         * twice, which the values' ids absorb (a service and a reader skip a value they saw);
         * a publish gives up at [publishTimeout] with [RedisUnavailableException]. While the
         * master has fewer than [replicas] replicas connected, the core waits as in an outage.
         * Costs one round trip per operation and the replicas' lag. Default 0: no waiting.
         */
        @JvmOverloads
        public fun replicaAcks(replicas: Int, timeout: Duration = Duration.ofSeconds(1)): Builder = apply {
            require(replicas >= 0) { "replica acks must be 0 or more, was $replicas" }
            require(timeout >= Duration.ofMillis(1) && timeout <= MAX_REPLICA_ACK_TIMEOUT) {
                "replica ack timeout must be within 1 ms..${MAX_REPLICA_ACK_TIMEOUT.seconds} s (a socket waits for it), was $timeout"
            }
            settings = settings.copy(replicaAcks = if (replicas == 0) null else ReplicaAcks(replicas, timeout))
        }

        /** Encodes values with [codec] (default: [KryoCodec.standard]). */
        public fun codec(codec: OptimusCodec): Builder = apply { settings = settings.copy(codec = codec) }

        /**
         * Runs only the named services in this process; the others run elsewhere. By default a
         * core hosts every service. Names are chain names (a linked chain's services are the
         * chains it was linked from), and those of filters, listeners, combinators of sources
         * (`combineLatest(a|b)`, ...) and timers: the services of [topology]. A chain's service
         * starts once the chain is used in this process ([dev.prime.Chain.toBlock], a link, a
         * template, a source's `then`), so declare the topology as the other processes do, its
         * `toBlock()` calls too; [start] logs one WARN naming the chains named here that nothing
         * used by then (they run nowhere, and calls to them wait out [callTimeout]).
         */
        public fun hosts(vararg services: String): Builder = hosts(services.toList())

        /** Like [hosts], from a collection. */
        public fun hosts(services: Collection<String>): Builder = apply {
            settings = settings.copy(hosts = services.toSet())
        }

        /**
         * How the processes that host [service] share it (see [Hosting]); default [Hosting.EXCLUSIVE]:
         * one host, and a second process naming it in [hosts] fails `start()`.
         * - [Hosting.ORDERED]: one active host; other hosts stand by (their `start()` succeeds) and
         *   one takes over within about [leaseTime] of the active host's death (a third of it after
         *   a close), processing first what the old host had taken: order kept, nothing lost.
         * - [Hosting.UNORDERED]: competing consumers: every host takes from the input at once, each
         *   into its own processing list; a dead host's list goes back to the input within about
         *   [leaseTime] (at once when it closes). A value's results are stored once; no order.
         *   Refused at `start()` (an [IllegalArgumentException] naming the service, the isolated
         *   chain and the fix) for a service that runs for an isolated chain (`isolate(chain)`: its
         *   own, each chain of a linked chain, a template's parts, a repeater's chain), whose hosts
         *   would run it for two calls at once; give those [Hosting.EXCLUSIVE] or [Hosting.ORDERED].
         *
         * Only chains' services take a mode (combinators, timers and generic services are exclusive),
         * and only those this process used by `start()` (`toBlock()`, a link, a template or a source's
         * `then()`): `start()` refuses a mode for a chain nothing used, whose service does not run.
         * Every process that hosts the service must give the same mode: `start()` of one that
         * disagrees with the running hosts fails with an [IllegalStateException] that names the
         * service, both modes and the fix. A process that does not host the service ignores its mode.
         */
        public fun hosting(service: String, hosting: Hosting): Builder = apply {
            require(service.isNotBlank()) { "the service of hosting(...) must be named" }
            settings = settings.copy(hostingModes = settings.hostingModes + (service to hosting))
        }

        /** How many times an asynchronous service retries a failed value before giving up on it (default 0). */
        public fun retries(retries: Int): Builder = apply {
            require(retries >= 0) { "retries must be 0 or more, was $retries" }
            settings = settings.copy(retries = retries)
        }

        /**
         * How long a synchronous call waits for its reply (default 60 s); `Duration.ZERO` waits
         * as long as it takes. The bound holds while Redis is unreachable too (within about a
         * second), and over a slow link for a timeout of at least three round trips: the call
         * then fails with [RedisUnavailableException] if Redis could not be reached, or with a
         * [dev.prime.PrimeException] saying the service did not reply if Redis answered.
         */
        public fun callTimeout(timeout: Duration): Builder = apply {
            require(!timeout.isNegative) { "call timeout must not be negative, was $timeout" }
            settings = settings.copy(callTimeout = timeout.takeUnless { it.isZero })
        }

        /**
         * How long a process counts as alive after its last heartbeat (default 5 s, at least
         * 300 ms, at most 24 h; the heartbeat runs every third of it). It bounds how long readers
         * and reply lists of a killed process stay in Redis, and how long a successor waits in
         * `start()` to take over the services of a killed host.
         *
         * @throws IllegalArgumentException if [leaseTime] is shorter than 300 ms or longer than 24 h
         */
        public fun leaseTime(leaseTime: Duration): Builder = apply {
            require(leaseTime >= MIN_LEASE_TIME) {
                "lease time must be at least ${MIN_LEASE_TIME.toMillis()} ms (shorter leases lapse on ordinary GC pauses), " +
                    "was $leaseTime"
            }
            require(leaseTime <= MAX_LEASE_TIME) {
                "lease time must be at most ${MAX_LEASE_TIME.toHours()} h (a killed process's services wait that long " +
                    "for a successor), was $leaseTime"
            }
            settings = settings.copy(leaseTime = leaseTime)
        }

        /**
         * The most values a service's input queue holds (default 100,000), for every service
         * without a limit of its own. A service's input is a queue, never trimmed: a publish that
         * would put it over its limit waits for room up to [publishTimeout] and then throws
         * [QueueFullException], publishing nothing.
         */
        public fun queueLimit(limit: Int): Builder = apply {
            require(limit > 0) { "queue limit must be positive, was $limit" }
            settings = settings.copy(queueLimit = limit)
        }

        /**
         * The queue limit of [service] (as the user named it), instead of the default [queueLimit].
         * [start] logs a WARN naming every such service that is not a service of the core's chains
         * by then (a misspelt name; or one declared later, which the limit then applies to).
         */
        public fun queueLimit(service: String, limit: Int): Builder = apply {
            require(limit > 0) { "queue limit of service '$service' must be positive, was $limit" }
            settings = settings.copy(queueLimits = settings.queueLimits + (service to limit))
        }

        /**
         * The longest [EventBlock.publish] and [publishAll] wait (default: the config's
         * [CoreConfig.publishTimeout], 10 s unless set): for room in a full service queue, then
         * [QueueFullException]; for an unreachable Redis, then [RedisUnavailableException].
         */
        public fun publishTimeout(timeout: Duration): Builder = apply {
            require(!timeout.isNegative) { "publish timeout must not be negative, was $timeout" }
            settings = settings.copy(publishTimeout = timeout)
        }

        /**
         * The largest encoded value (default 16 MiB): a bigger one is refused at publish or call
         * time with [ValueTooLargeException]; a bigger entry found in Redis is dead-lettered
         * (keeping its first KiB, not the blob). Every process of a topology should agree.
         */
        public fun maxValueBytes(bytes: Int): Builder = apply {
            require(bytes > 0) { "max value bytes must be positive, was $bytes" }
            settings = settings.copy(maxValueBytes = bytes)
        }

        /**
         * The most dead letters kept per service (default 10,000): older ones are dropped, and
         * counted ([trimmedDeadLetters]).
         */
        public fun deadLetterLimit(limit: Int): Builder = apply {
            require(limit > 0) { "dead-letter limit must be positive, was $limit" }
            settings = settings.copy(deadLetterLimit = limit)
        }

        /** The bytes a service step takes at most (default 8 MiB; always at least one entry). */
        internal fun batchBytes(bytes: Int): Builder = apply {
            require(bytes > 0) { "batch bytes must be positive, was $bytes" }
            settings = settings.copy(batchBytes = bytes)
        }

        /** The bytes a frame (many values in one Redis entry) holds at most (default 1 MiB; a single value may need more). */
        internal fun frameBytes(bytes: Int): Builder = apply {
            require(bytes > 0) { "frame bytes must be positive, was $bytes" }
            settings = settings.copy(frameBytes = bytes)
        }

        /** Makes the core: starts an embedded Redis unless [redis] was given, and checks that Redis answers. */
        public fun build(): OptimusCore = OptimusCore(config, settings)
    }

    internal data class Settings(
        val redisUrl: String? = null,
        val codec: OptimusCodec? = null,
        val hosts: Set<String>? = null,
        val retries: Int = 0,
        val callTimeout: Duration? = Duration.ofSeconds(60),
        val leaseTime: Duration = Duration.ofSeconds(5),
        val publishTimeout: Duration? = null, // null: the CoreConfig's
        val maxValueBytes: Int = 16 * 1024 * 1024,
        val queueLimit: Int = 100_000,
        val queueLimits: Map<String, Int> = emptyMap(),
        val deadLetterLimit: Int = 10_000,
        val batchBytes: Int = StepRules.DEFAULT_BATCH_BYTES,
        val replicaAcks: ReplicaAcks? = null,
        val frameBytes: Int = Frame.DEFAULT_BYTES,
        val hostingModes: Map<String, Hosting> = emptyMap(),
    )

    public companion object {
        private val LOG = LoggerFactory.getLogger(OptimusCore::class.java)

        /** The Optimus core whose own thread the current thread is ([callOfAnotherCore]); `null` on any other thread. */
        private val ownerOfThread = ThreadLocal<OptimusCore?>()
        private const val FAILURES_KEPT = 1024
        private val CLEANUP_TIMEOUT = Duration.ofSeconds(2)

        /**
         * How long a close spends at most on its clean-up connection (connecting, logging in and
         * the pipeline that removes its keys, together): [CLEANUP_TIMEOUT], or half of
         * [shutdownTimeout] if that is less, so that a close on a Redis that does not answer
         * stays within its shutdown timeout. Connecting (at most this long) and logging in (at most
         * this long) leave the pipeline what is left of it, at least a millisecond.
         */
        internal fun cleanupNanos(shutdownTimeout: Duration): Long =
            minOf(CLEANUP_TIMEOUT.toNanos(), boundedNanos(shutdownTimeout) / 2).coerceAtLeast(1_000_000)
        private val DELETE_KEYS_TIMEOUT = Duration.ofSeconds(10)
        private val DEAD_LETTERS_TIMEOUT = Duration.ofSeconds(10)

        /** What start(), and a declaration after it, may wait for: Redis, or another process's host lease. */
        /** What a publish or a read may wait for: Redis, in an outage, or the answer of a Redis that stopped answering. */
        internal const val WAITED_FOR_ANSWER = "for Redis (to reach it again, or for its answer)"
        private const val WAITED_FOR_REDIS_OR_LEASE = "for Redis (to reach it again, or for another process's host lease to lapse)"
        private const val DELETE_KEYS_BATCH = 1_000
        private val MIN_LEASE_TIME = Duration.ofMillis(300)
        private val MAX_LEASE_TIME = Duration.ofHours(24)
        private const val STANDBY_MIN_WAIT_MS = 10L
        private val MIN_REPLY_TTL = Duration.ofMinutes(10)
        private val MAX_REPLICA_ACK_TIMEOUT = Duration.ofSeconds(5)

        /** An envelope's header, payload marker and longest reply key. */
        private const val ENVELOPE_OVERHEAD = 16 + 2 + 0xFFFF

        /** Settings for a core; call [Builder.build]. */
        @JvmStatic
        public fun builder(): Builder = Builder()
    }
}

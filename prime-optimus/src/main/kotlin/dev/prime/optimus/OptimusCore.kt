package dev.prime.optimus

import dev.prime.Block
import dev.prime.Chain
import dev.prime.ChainFailedException
import dev.prime.CoreClosedException
import dev.prime.CoreConfig
import dev.prime.EventBlock
import dev.prime.PrimeCore
import dev.prime.Reader
import dev.prime.Source
import kotlinx.coroutines.CoroutineName
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.ExecutorCoroutineDispatcher
import kotlinx.coroutines.SupervisorJob
import kotlinx.coroutines.asCoroutineDispatcher
import kotlinx.coroutines.cancel
import kotlinx.coroutines.launch
import kotlinx.coroutines.runBlocking
import kotlinx.coroutines.withTimeoutOrNull
import org.slf4j.LoggerFactory
import redis.clients.jedis.params.SetParams
import java.nio.charset.StandardCharsets.UTF_8
import java.time.Duration
import java.util.Collections
import java.util.Objects
import java.util.UUID
import java.util.concurrent.ConcurrentHashMap
import java.util.concurrent.ConcurrentLinkedQueue
import java.util.concurrent.ExecutorService
import java.util.concurrent.Executors
import java.util.concurrent.atomic.AtomicInteger
import java.util.function.Consumer
import java.util.function.Predicate

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
 *   them atomically and trims each to [CoreConfig.sourceRetention]. A chain linked to a source is
 *   one of its readers.
 * - Templates are the generic ones of [PrimeCore]: a template chain is one service whose block
 *   calls the services of the chains it was made of.
 *
 * ## Distribution
 * Every process declares the same topology, in the same order, with the same core name (the
 * name is the Redis namespace) and an agreeing codec; each one is told which services it hosts
 * ([Builder.hosts]); the others are remote. Values wait in Redis until a host takes them.
 *
 * ## Guarantees beyond every media's
 * - A value taken by a service stays in Redis until its result is stored, in the same atomic step
 *   (a Lua script, all keys of a topology in one hash slot); after a crash or a lost connection a
 *   service first finishes what it had taken. With a durable Redis, nothing accepted is lost.
 * - Values have ids; one pushed twice by a retry is processed once.
 * - Bytes that cannot be decoded, and values whose block failed (after [Builder.retries]), go to
 *   the service's dead-letter list ([deadLetters]); the service goes on.
 * - [close] closes every connection, which wakes every blocked call, and leaves no thread.
 *
 * Threading: like every core, declaring is thread-safe; blocks of hosted services run on the
 * core's threads (`prime-<core>-optimus-<n>`), one value at a time per service.
 */
public class OptimusCore private constructor(config: CoreConfig, settings: Settings) : PrimeCore("optimus", config) {

    /** A core on an embedded Redis of its own (see [EmbeddedRedis]), hosting every service. */
    public constructor() : this(CoreConfig.defaults())

    /** A core with [config], on an embedded Redis of its own, hosting every service. */
    public constructor(config: CoreConfig) : this(config, Settings())

    private val embedded: EmbeddedRedis?
    private val endpoint: RedisEndpoint
    internal val keys: Keys = Keys(name())
    internal val codec: OptimusCodec = settings.codec ?: KryoCodec.standard()
    internal val connections: RedisConnections
    internal val ids: ValueIds = ValueIds()
    internal val retries: Int = settings.retries
    internal val callTimeout: Duration? = settings.callTimeout
    private val hosts: Set<String>? = settings.hosts
    private val instance = UUID.randomUUID().toString()

    private val services = ConcurrentHashMap<String, StageService>()
    private val launched: MutableSet<String> = ConcurrentHashMap.newKeySet()
    private val readers: MutableSet<Pair<SourceKeys, ByteArray>> = ConcurrentHashMap.newKeySet()
    private val subscriptions = ConcurrentLinkedQueue<EventBlock.Subscription>()
    private val idleSlots = ConcurrentLinkedQueue<CallerSlot>()
    private val allSlots = ConcurrentLinkedQueue<CallerSlot>()
    private val slotNumbers = AtomicInteger()
    private val publishers = ConcurrentLinkedQueue<RedisSession>()
    private val failures = Collections.synchronizedMap(object : LinkedHashMap<Long, ChainFailedException>() {
        override fun removeEldestEntry(eldest: MutableMap.MutableEntry<Long, ChainFailedException>?) = size > FAILURES_KEPT
    })

    private val threadNumbers = AtomicInteger()
    private val threads = ConcurrentLinkedQueue<Thread>()
    private val executor: ExecutorService = Executors.newCachedThreadPool { task ->
        Thread(task, "prime-${name()}-optimus-${threadNumbers.incrementAndGet()}").apply {
            isDaemon = true
            threads += this
        }
    }
    private val dispatcher: ExecutorCoroutineDispatcher = executor.asCoroutineDispatcher()
    private val supervisor = SupervisorJob()
    private val scope = CoroutineScope(supervisor + dispatcher + CoroutineName("optimus-${name()}"))

    init {
        val url = settings.redisUrl
        embedded = if (url == null) EmbeddedRedis.start() else null
        endpoint = RedisEndpoint.parse(url ?: embedded!!.uri)
        connections = RedisConnections(endpoint, name())
        try {
            RedisSession(connections).use { it.once { jedis -> jedis.ping() } }
        } catch (e: Exception) {
            shutdownResources()
            throw dev.prime.PrimeException("cannot reach Redis at $endpoint: $e", e)
        }
    }

    /** The URL of the Redis this core uses (password hidden). */
    public val redisUrl: String get() = endpoint.toString()

    // ------------------------------------------------------------------ chains

    override fun <I, O> newChain(name: String, block: Block<I, O>): Chain<I, O> =
        OptimusChain(this, name, listOf(StageSpec(name, chainLogic(block))))

    override fun <I, M, O> link(first: Chain<I, M>?, second: Chain<M, O>?): Chain<I, O> {
        requireChains(first, second)
        if (first is OptimusChain<I, M> && first.core() === this && second is OptimusChain<M, O> && second.core() === this) {
            val stages = first.take() + second.take()
            return OptimusChain(this, derivedName(first.name() + ">" + second.name(), "link"), stages)
        }
        return super.link(first, second)
    }

    // ------------------------------------------------------------------ sources

    override fun <T> newSource(name: String, events: EventBlock<T>): Source<T> {
        val source = OptimusSource<T>(this, name)
        subscriptions += events.subscribe { value ->
            try {
                publish(source.keys, listOf(Envelope.value(ids.next(), encode(value))))
            } catch (_: CoreClosedException) {
                // the core closed while this value was on its way: nobody can read it any more
            }
        }
        return source
    }

    override fun <I, O> link(source: Source<I>?, chain: Chain<I, O>?): Source<O> {
        requireSource(source)
        requireChains(chain)
        if (source !is OptimusSource<I> || source.core() !== this) return super.link(source, chain)
        val stages = if (chain is OptimusChain<I, O> && chain.core() === this) {
            chain.take()
        } else {
            listOf(StageSpec(derivedName("hosted(" + chain!!.name() + ")", "hosted"), chainLogic(chain.toBlock())))
        }
        val output = OptimusSource<O>(this, derivedName(source.name() + ">" + chain!!.name(), "link"))
        bindToSource(source, stages, output)
        return output
    }

    @Suppress("UNCHECKED_CAST")
    override fun <T> filterSource(source: Source<T>?, predicate: Predicate<in T>?): Source<T> {
        Objects.requireNonNull(predicate, "predicate must not be null")
        if (!isOwn(source)) return super.filterSource(source, predicate)
        return serviceOn(source!!, "filter", publishes = true) { input, emit -> if (predicate!!.test(input as T)) emit(input) }!!
    }

    @Suppress("UNCHECKED_CAST")
    override fun <T, R> flatMapSource(source: Source<T>?, block: Block<in T, out Iterable<R>>?): Source<R> {
        Objects.requireNonNull(block, "block must not be null")
        if (!isOwn(source)) return super.flatMapSource(source, block)
        return serviceOn(source!!, "flatMap", publishes = true) { input, emit -> block!!.process(input as T)?.forEach(emit) }!!
    }

    @Suppress("UNCHECKED_CAST")
    override fun <T> listenSource(source: Source<T>?, listener: Consumer<in T>?) {
        Objects.requireNonNull(listener, "listener must not be null")
        if (!isOwn(source)) return super.listenSource(source, listener)
        serviceOn<Any>(source!!, "listen", publishes = false) { input, _ -> listener!!.accept(input as T) }
    }

    /** Checks [source] like every link does; whether it is a source of this core (else the generic service is used). */
    private fun isOwn(source: Source<*>?): Boolean {
        requireSource(source)
        return source is OptimusSource<*> && source.core() === this
    }

    /** One service reading [source] and running [logic], named `kind(source)`; its output source if it [publishes]. */
    private fun <R> serviceOn(source: Source<*>, kind: String, publishes: Boolean, logic: StageLogic): OptimusSource<R>? {
        val name = derivedName(kind + "(" + source.name() + ")", kind)
        val output = if (publishes) OptimusSource<R>(this, name) else null
        bindToSource(source as OptimusSource<*>, listOf(StageSpec(name, logic)), output)
        return output
    }

    /**
     * Publishes [values] to [source] in one atomic step (one round trip), in order: the fast way
     * to feed a source at high rates, where [EventBlock.publish] costs a round trip per value.
     *
     * @throws IllegalArgumentException if the source is not an Optimus source of this core, or a
     *     value is `null` or of a type the codec does not allow
     * @throws IllegalStateException if the core is not started yet
     */
    public fun <T> publishAll(source: Source<T>, values: Iterable<T>) {
        checkOpen()
        require(source is OptimusSource<T> && source.core() === this) { "$source is not a source of $this" }
        val envelopes = values.map { value ->
            requireNotNull(value) { "sources carry no null values" }
            Envelope.value(ids.next(), encode(value))
        }
        if (envelopes.isNotEmpty()) publish(source.keys, envelopes)
    }

    // ------------------------------------------------------------------ dead letters

    /** The values service [service] gave up on, oldest first (see [DeadLetter]). */
    public fun deadLetters(service: String): List<DeadLetter> {
        checkOpen()
        return withSession { session -> session.retrying { it.lrange(keys.deadLetters(service), 0, -1) } }
            .map { DeadLetter.decode(service, it) }
    }

    /** Deletes the dead letters of [service]; returns how many there were. */
    public fun clearDeadLetters(service: String): Int {
        checkOpen()
        return withSession { session ->
            session.retrying { jedis ->
                val transaction = jedis.multi()
                val length = transaction.llen(keys.deadLetters(service))
                transaction.del(keys.deadLetters(service))
                transaction.exec()
                length.get().toInt()
            }
        }
    }

    /**
     * The asynchronous services this process runs: the services of used chains it hosts, and the
     * in-process services of links to sources of other cores.
     */
    override fun serviceNames(): Set<String> =
        super.serviceNames() + services.keys.filter(::isHosted)

    // ------------------------------------------------------------------ lifecycle

    override fun onStart() {
        checkCodecAgreement()
        hosts?.let { wanted ->
            val unknown = wanted - services.keys
            require(unknown.isEmpty()) {
                "core '${name()}' is told to host $unknown, which its topology does not declare (declare the whole " +
                    "topology before start()); its services: ${services.keys.sorted()}"
            }
        }
        services.values.forEach(::launchIfHosted)
    }

    override fun onClose() {
        // close() from a service's or listener's own thread must not wait for that thread
        val ownThread = Thread.currentThread() in threads
        subscriptions.forEach { it.close() }
        subscriptions.clear()
        scope.cancel()
        val cleanup = try {
            endpoint.connect("prime-${name()}-cleanup", CLEANUP_TIMEOUT, CLEANUP_TIMEOUT)
        } catch (_: Exception) {
            null
        }
        connections.closeAll() // wakes every blocked read
        cleanup?.use { jedis ->
            try {
                val pipeline = jedis.pipelined()
                for ((source, list) in readers) {
                    pipeline.srem(source.readers, list)
                    pipeline.del(list, keys.processingOf(list), keys.missedOf(list))
                }
                for (slot in 1..slotNumbers.get()) pipeline.del(replyKey(slot))
                pipeline.sync()
            } catch (e: Exception) {
                LOG.debug("core '{}' could not remove its readers and reply lists: {}", name(), e.toString())
            }
        }
        val timeout = config().shutdownTimeout()
        // A service closing its own core (a listener) cannot wait for itself: it waits for the
        // other services' threads only, in shutdownResources.
        if (!ownThread) {
            runBlocking { withTimeoutOrNull(timeout.toMillis()) { supervisor.join() } }
                ?: LOG.warn("core '{}': services still running after {}", name(), timeout)
        }
        shutdownResources()
    }

    /** Stops the threads (all but the calling one, which ends when its service returns) and the embedded Redis. */
    private fun shutdownResources() {
        val current = Thread.currentThread()
        var interrupted = false
        try {
            dispatcher.close()
            executor.shutdown()
            // every service but the calling one: a service closing its own core goes on until it returns
            threads.filter { it !== current }.forEach(Thread::interrupt)
            val deadline = System.nanoTime() + config().shutdownTimeout().toNanos()
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

    /** Fails at once if [start] was not called: before it, no service of this process runs. */
    internal fun checkStarted(what: String) {
        check(isStarted) {
            "$what of core '${name()}' before start(): start() was not called; declare the topology, then call " +
                "core.start(), then call chains and read sources"
        }
    }

    internal fun encode(value: Any?): ByteArray? = value?.let(codec::encode)

    internal fun <I, O> bindForCalls(chainName: String, stages: List<StageSpec>): Block<I, O> {
        bind(stages, null)
        return RemoteCall(this, chainName, keys.serviceInput(stages.first().name))
    }

    internal fun <T> newReader(source: OptimusSource<T>): Reader<T> {
        checkOpen()
        val list = keys.reader(UUID.randomUUID().toString())
        register(source.keys, list)
        readers += source.keys to list
        return OptimusReader(this, source.keys, list)
    }

    /** A closed reader: the core's close need not remove its lists. */
    internal fun forgetReader(list: ByteArray) {
        readers.removeIf { it.second === list }
    }

    internal fun borrowSlot(): CallerSlot = idleSlots.poll() ?: CallerSlot(this, replyKey(slotNumbers.incrementAndGet())).also {
        allSlots += it
    }

    internal fun returnSlot(slot: CallerSlot) {
        if (isClosed) slot.close() else idleSlots += slot
    }

    internal fun rememberFailure(id: Long, failure: ChainFailedException) {
        failures[id] = failure
    }

    internal fun takeFailure(id: Long): ChainFailedException? = failures.remove(id)

    /**
     * Gives a failure to the error handler as the user knows it: a [ChainFailedException] (a chain
     * called from this service failed) under the failing chain's name, with its block's own throwable.
     */
    internal fun reportFailure(service: String, input: Any, error: Throwable) {
        val failed = error as? ChainFailedException
        try {
            if (failed?.cause != null) {
                config().errorHandler().handle(failed.chainName(), input, failed.cause)
            } else {
                config().errorHandler().handle(service, input, error)
            }
        } catch (e: VirtualMachineError) {
            throw e
        } catch (e: Throwable) {
            LOG.warn("the error handler of core '{}' failed on service '{}': {}", name(), service, e.toString())
        }
    }

    // ------------------------------------------------------------------ internals

    private fun replyKey(slot: Int) = keys.reply("$instance:$slot")

    private fun bindToSource(source: OptimusSource<*>, stages: List<StageSpec>, output: OptimusSource<*>?) {
        register(source.keys, keys.serviceInput(stages.first().name))
        bind(stages, output?.keys)
    }

    private fun bind(stages: List<StageSpec>, output: SourceKeys?) {
        stages.forEachIndexed { index, stage ->
            val last = index == stages.size - 1
            val service = StageService(
                stage.name,
                this,
                stage.logic,
                if (last) null else keys.serviceInput(stages[index + 1].name),
                if (last) output else null,
            )
            check(services.putIfAbsent(stage.name, service) == null) { "service '${stage.name}' is bound twice" }
            if (isStarted) launchIfHosted(service)
        }
    }

    private fun isHosted(service: String) = hosts == null || service in hosts

    private fun launchIfHosted(service: StageService) {
        if (!isHosted(service.name) || !launched.add(service.name) || isClosed) return
        scope.launch(CoroutineName(service.name)) { service.run() }
    }

    private fun register(source: SourceKeys, list: ByteArray) {
        withSession { session -> session.retrying { Script.REGISTER.run(it, listOf(source.readers, source.log, list), emptyList()) } }
    }

    private fun publish(source: SourceKeys, envelopes: List<ByteArray>) {
        checkStarted("publishing to an Optimus source")
        withSession { session ->
            session.retrying { StepBatch(source.log, source.log, source).apply { envelopes.forEach(::publish) }.run(it, 0, 0) }
        }
    }

    private fun <T> withSession(action: (RedisSession) -> T): T {
        val session = publishers.poll() ?: RedisSession(connections)
        try {
            return action(session)
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
            "core '${name()}' uses a codec with fingerprint $mine, but this topology's processes use $theirs: register " +
                "the same types in the same order in every process (or delete the Redis key " +
                "'${keys.codec.toString(UTF_8)}' if the types changed on purpose)"
        }
    }

    private fun <I, O> chainLogic(block: Block<I, O>) = StageLogic { input, emit ->
        @Suppress("UNCHECKED_CAST")
        emit(block.process(input as I))
    }

    /** Settings of an [OptimusCore]; [build] makes the core. */
    public class Builder internal constructor() {
        private var config: CoreConfig = CoreConfig.defaults()
        private var settings = Settings()

        /** The settings every media shares (name, retention, error handler, shutdown timeout). */
        public fun config(config: CoreConfig): Builder = apply { this.config = config }

        /**
         * Uses the Redis at [url] (`redis://[user[:password]@]host[:port][/database]`, or
         * `rediss://` for TLS) instead of starting an embedded one.
         *
         * @throws IllegalArgumentException if the URL is malformed; the message says how to fix it
         */
        public fun redis(url: String): Builder = apply {
            RedisEndpoint.parse(url)
            settings = settings.copy(redisUrl = url)
        }

        /** Encodes values with [codec] (default: [KryoCodec.standard]). */
        public fun codec(codec: OptimusCodec): Builder = apply { settings = settings.copy(codec = codec) }

        /**
         * Runs only the named services in this process; the others run elsewhere. By default a
         * core hosts every service. Names are chain names (a linked chain's services are the
         * chains it was linked from).
         */
        public fun hosts(vararg services: String): Builder = hosts(services.toList())

        /** Like [hosts], from a collection. */
        public fun hosts(services: Collection<String>): Builder = apply {
            settings = settings.copy(hosts = services.toSet())
        }

        /** How many times an asynchronous service retries a failed value before giving up on it (default 0). */
        public fun retries(retries: Int): Builder = apply {
            require(retries >= 0) { "retries must be 0 or more, was $retries" }
            settings = settings.copy(retries = retries)
        }

        /**
         * How long a synchronous call waits for its reply (default 60 s); `Duration.ZERO` waits
         * as long as it takes. The bound holds while Redis is unreachable too (within about a
         * second): the call then fails with [RedisUnavailableException], or with a
         * [dev.prime.PrimeException] saying the service did not reply.
         */
        public fun callTimeout(timeout: Duration): Builder = apply {
            require(!timeout.isNegative) { "call timeout must not be negative, was $timeout" }
            settings = settings.copy(callTimeout = timeout.takeUnless { it.isZero })
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
    )

    public companion object {
        private val LOG = LoggerFactory.getLogger(OptimusCore::class.java)
        private const val FAILURES_KEPT = 1024
        private val CLEANUP_TIMEOUT = Duration.ofSeconds(2)

        /** Settings for a core; call [Builder.build]. */
        @JvmStatic
        public fun builder(): Builder = Builder()
    }
}

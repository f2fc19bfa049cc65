package dev.prime;

import dev.prime.internal.Deadlines;
import dev.prime.internal.ServiceThreads;
import dev.prime.topology.Topology;
import java.util.List;
import java.util.Objects;
import java.util.Set;
import java.util.concurrent.ConcurrentHashMap;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicInteger;
import java.util.concurrent.atomic.AtomicLong;
import java.util.function.Consumer;
import java.util.function.Function;
import java.util.function.Predicate;
import java.util.function.Supplier;
import org.slf4j.Logger;
import org.slf4j.LoggerFactory;

/**
 * The media layer: turns blocks into chains and event blocks into sources, links them, and runs
 * the services. Switching media is switching the subclass that is created:
 *
 * <pre>{@code
 * try (PrimeCore core = new LibertyCore()) {          // or new RadiantCore(), new OptimusCore()
 *   Chain<Ticks, Pose> odometry = core.chain("odometry", new Odometry());
 *   Chain<Ticks, Command> control = odometry.then(core.chain("planner", new Planner()));
 *   core.start();
 *   Block<Ticks, Command> controller = control.toBlock();
 *   Command command = controller.process(ticks);
 * }
 * }</pre>
 *
 * <h2>What every media guarantees</h2>
 * <ul>
 *   <li>Chains are single use ({@link ChainAlreadyUsedException}); values leave chains and sources
 *       in the order they entered.
 *   <li>Sources are broadcast with bounded retention ({@link CoreConfig#sourceRetention()}).
 *   <li>A chain linked to a source runs as one service in the media that fuse chains (linking
 *       chains first and then linking the combined chain to a source makes one service, not one
 *       per chain); a distributed media may keep one service per chain, connected without an
 *       extra hop.
 *   <li>A block that throws reaches a synchronous caller as {@link ChainFailedException}; in a
 *       service it goes to the {@link ErrorHandler} and the service carries on (see {@link Block}
 *       for every kind of throwable).
 *   <li>A link or template that throws consumes nothing: every chain given to it stays usable.
 *       More generally, a declaration that fails leaves the chain unused; it can be made again: a
 *       {@link Chain#toBlock()}, a link of a chain to a source, a timer or a combinator that fails
 *       after {@link #start()} (on Optimus, which waits for Redis through an outage: that wait
 *       interrupted, or another process hosting the service) leaves nothing of it behind, so the
 *       same call works once the cause is gone (see {@link Chain#toBlock()} for the one exception).
 *   <li>Every blocking wait (a reader's {@code take}, a sync collector, a caller waiting for an
 *       isolated chain, a repeater between rounds) ends when its thread is interrupted or the core
 *       closes. Where such a wait runs on a service's thread for a caller elsewhere (Optimus), it
 *       also ends when that caller gives up (interrupted, or its timeout passed): the service goes
 *       on to its next call, and a sync collector keeps a value that came meanwhile for its next
 *       call. {@link #close()} may be called from a service's own thread (a listener).
 *   <li>{@link #close()} stops every service within {@link CoreConfig#shutdownTimeout()} and
 *       releases every thread and connection; a closed core throws {@link CoreClosedException}.
 * </ul>
 *
 * <h2>Threading</h2>
 * Declaring the topology (chains, sources, links, templates) is thread-safe and allowed at any
 * time before {@link #close()}; services declared after {@link #start()} start at once.
 *
 * <h2>For media authors</h2>
 * A media is a compiler of the topology model. Every declaration is recorded as a node with its
 * logic ({@link NodeLogic}) and compiled at once by the media's {@link #chainCompiler()}, which a
 * media implements; templates it does not compile in its own way become the core's generic
 * blocks. Sources and their services are the core's in-memory ones, one thread per service,
 * unless the media has a {@link #sourceCompiler()} (Optimus: Redis lists and services). The
 * protected methods are all a media uses of this class.
 */
public abstract class PrimeCore implements AutoCloseable {

  private static final ConcurrentHashMap<String, AtomicInteger> CORE_COUNTERS =
      new ConcurrentHashMap<>();
  private static final AtomicLong CREATED = new AtomicLong();
  private static final Logger LOG = LoggerFactory.getLogger(PrimeCore.class);
  private static final long CLOSE_WAIT_SLACK_MILLIS = 30_000;

  private enum State {
    NEW,
    STARTED,
    FAILED, // start() threw: closed only by close()
    CLOSED
  }

  private final CoreConfig config;
  private final String name;
  private final String media;
  private final TopologyRecorder recorder = new TopologyRecorder(this);
  private volatile ModelCompiler<?> compiler; // made on first use: the media's compilers
  private final ServiceThreads services;
  private final InProcessServices inProcess;
  private final Combinators combinators;
  private final LifecycleHooks hooks = new LifecycleHooks(this);
  private final Object lifecycle = new Object();
  private volatile State state = State.NEW;
  private volatile boolean started; // start() was called (and accepted), closed or not
  private volatile Throwable startFailure; // what start() threw, if it did
  private volatile Thread closingThread; // the thread of the first close(), set under lifecycle
  private final CountDownLatch closed = new CountDownLatch(1); // the first close() has finished
  private final long creationOrder = CREATED.incrementAndGet();

  /**
   * @param media the media's short name, for generated core names ({@code liberty-1})
   * @param config the settings
   */
  protected PrimeCore(String media, CoreConfig config) {
    this.media = Objects.requireNonNull(media, "media");
    this.config = Objects.requireNonNull(config, "config must not be null");
    this.name =
        config.name() != null
            ? config.name()
            : media + "-" + CORE_COUNTERS.computeIfAbsent(media, k -> new AtomicInteger()).incrementAndGet();
    this.services = new ServiceThreads(name, () -> new CoreClosedException(name));
    this.inProcess = new InProcessServices(this, services);
    this.combinators = new Combinators(this, services);
  }

  /** The order in which cores take each other's declaration locks ({@link DeclarationLock}). */
  final long creationOrder() {
    return creationOrder;
  }

  /** {@return the core's name (from {@link CoreConfig#name()} or generated)} */
  public final String name() {
    return name;
  }

  /** {@return the core's settings} */
  public final CoreConfig config() {
    return config;
  }

  /**
   * {@return whether {@link #start()} was called (and accepted); stays true after {@link
   * #close()}, and false for a core closed without being started}
   */
  public final boolean isStarted() {
    return started;
  }

  /** {@return whether {@link #close()} was called} */
  public final boolean isClosed() {
    return state == State.CLOSED;
  }

  // ---------------------------------------------------------------- chains

  /**
   * Creates a chain named {@code chain-N}.
   *
   * @param block the logic
   * @param <I> input type
   * @param <O> output type
   * @return a new chain of this core
   */
  public final <I, O> Chain<I, O> chain(Block<I, O> block) {
    Objects.requireNonNull(block, "block must not be null");
    ensureOpen();
    return declared(() -> compiled(topologyRecorder().blockChain(null, block)));
  }

  /**
   * Creates a named chain.
   *
   * @param name unique in this core; 1 to 200 characters, no whitespace or braces
   * @param block the logic
   * @param <I> input type
   * @param <O> output type
   * @return a new chain of this core
   * @throws IllegalArgumentException if the name is invalid or taken
   */
  public final <I, O> Chain<I, O> chain(String name, Block<I, O> block) {
    Objects.requireNonNull(name, "name must not be null");
    Objects.requireNonNull(block, "block must not be null");
    ensureOpen();
    return declared(() -> compiled(topologyRecorder().blockChain(name, block)));
  }

  /**
   * Creates a named chain with a pseudoname: a readable name shown in the drawings of the
   * topology ({@code Wheel odometry (odometry)}) and given with every value the chain's outputs
   * record ({@link RecordedValue#pseudoname()}). The name stays what identifies the chain.
   *
   * @param name unique in this core; 1 to 200 characters, no whitespace or braces
   * @param pseudoname 1 to 120 characters, not only whitespace, no control characters
   * @param block the logic
   * @param <I> input type
   * @param <O> output type
   * @return a new chain of this core
   * @throws IllegalArgumentException if the name is invalid or taken or the pseudoname invalid
   */
  public final <I, O> Chain<I, O> chain(String name, String pseudoname, Block<I, O> block) {
    Objects.requireNonNull(name, "name must not be null");
    Objects.requireNonNull(block, "block must not be null");
    TopologyRecorder.checkPseudoname(pseudoname);
    ensureOpen();
    return declared(() -> compiled(Pseudonames.record(topologyRecorder(), name, pseudoname, block)));
  }

  /**
   * The media's compiler of the topology model's chain nodes: every chain of this core is
   * recorded in the model and compiled by it at once (see {@link ChainCompiler}). Called once,
   * when the first chain is made.
   *
   * @return the compiler
   */
  protected abstract ChainCompiler<?> chainCompiler();

  /** Compiles a chain node just recorded, consuming {@code parts} (checked, in the node's order). */
  private <I, O> Chain<I, O> compiled(String name, Chain<?, ?>... parts) {
    return model().chain(name, parts);
  }

  /** Declares a chain node made of {@code parts}: checks them, records, compiles and claims. */
  private <I, O> Chain<I, O> declaredChain(
      Function<TopologyRecorder, String> record, Chain<?, ?>... parts) {
    return declared(
        () -> {
          requireChains(parts);
          return compiled(record.apply(topologyRecorder()), parts);
        },
        parts);
  }

  /**
   * The media's compiler of the topology model's source nodes, or {@code null} (the default) for
   * the core's in-memory sources and services (see {@link SourceCompiler}). Called once, when the
   * first chain or source is made.
   *
   * @return the compiler, or {@code null}
   */
  protected SourceCompiler<?> sourceCompiler() {
    return null;
  }

  /**
   * This media's compiled form of a source, if it is one of this core's own in that form ({@link
   * MediaSource#compiledForm()}); {@code null} for any other source. Consumes nothing.
   *
   * @param source a source
   * @param form the type of this media's source form
   * @param <S> that type
   * @return the form, or {@code null}
   */
  protected final <S> S sourcePart(Source<?> source, Class<S> form) {
    return ModelCompiler.sourceForm(this, source, form);
  }

  /** Compiles the event source of a node just recorded (for the core's combinators). */
  <T> Source<T> newSource(String name, EventBlock<T> events) {
    return model().eventSource(name, events);
  }

  /**
   * Runs a declaration atomically: its checks, the nodes it records and the chains it consumes,
   * holding the declaration locks of this core and of the cores of the chains it takes.
   */
  private <T> T declared(Supplier<T> declaration, Chain<?, ?>... takes) {
    return DeclarationLock.run(this, declaration, takes);
  }

  /** The compiler of this core's model (made on first use: it asks the media for its compilers). */
  ModelCompiler<?> model() {
    ModelCompiler<?> c = compiler;
    if (c == null) {
      synchronized (lifecycle) {
        c = compiler;
        if (c == null) {
          c = new ModelCompiler<>(this, chainCompiler(), sourceCompiler(), inProcess);
          compiler = c;
        }
      }
    }
    return c;
  }

  /**
   * Links two chains: the result feeds {@code first}'s output to {@code second}. Consumes both. A
   * chain of another core is taken through its {@link Chain#toBlock()}. Like {@link
   * java.util.function.Function#andThen}, {@code second} may take any supertype of {@code
   * first}'s output.
   *
   * @param first runs first
   * @param second runs on the first chain's outputs
   * @param <I> input type
   * @param <M> type passed between the chains
   * @param <O> output type
   * @return the combined chain, named {@code first>second}
   */
  public final <I, M, O> Chain<I, O> link(Chain<I, M> first, Chain<? super M, O> second) {
    return declaredChain(recorder -> recorder.link(first, second), first, second);
  }

  /**
   * {@link Chain#then(Block)}: links {@code first} to a new chain made of {@code next}, in one
   * declaration, so that a link that is refused leaves no chain of the block behind.
   */
  final <I, M, O> Chain<I, O> linkBlock(Chain<I, M> first, Block<? super M, ? extends O> next) {
    return declared(() -> link(first, chain(Block.<M, O>narrow(next))), first);
  }

  // ---------------------------------------------------------------- templates

  /**
   * A chain that runs {@code then} for inputs that satisfy {@code condition}, else
   * {@code otherwise}. Consumes both chains. Each branch may take a supertype of the input and
   * return a subtype of the output (as {@link java.util.function.Function#andThen} allows).
   *
   * @param condition chooses the branch
   * @param then the chain for inputs that satisfy it
   * @param otherwise the chain for the others
   * @param <I> input type
   * @param <O> output type
   * @return the combined chain
   */
  public final <I, O> Chain<I, O> ifThenElse(
      Predicate<? super I> condition,
      Chain<? super I, ? extends O> then,
      Chain<? super I, ? extends O> otherwise) {
    Objects.requireNonNull(condition, "condition must not be null");
    return declaredChain(recorder -> recorder.ifElse(then, otherwise, condition), then, otherwise);
  }

  /**
   * A chain that runs {@code body} on each element of a list, in order, and returns the list of
   * its outputs. Consumes {@code body}, which may take a supertype of the elements and return a
   * subtype of the output elements. A {@code null} list fails the call with an exception whose
   * message (or a cause's) says "for-each input list must not be null"; the body is not run.
   *
   * @param body the chain for one element
   * @param <I> element type of the input
   * @param <O> element type of the output
   * @return the combined chain
   */
  public final <I, O> Chain<List<I>, List<O>> forEach(Chain<? super I, ? extends O> body) {
    return declaredChain(recorder -> recorder.forEach(body), body);
  }

  /**
   * A chain that gives each input to both chains and returns both outputs. Consumes them. Each
   * chain may take a supertype of the input, as with every union.
   *
   * @param a first chain
   * @param b second chain
   * @param <I> input type
   * @param <A> output of a
   * @param <B> output of b
   * @return the union
   */
  public final <I, A, B> Chain<I, Tuple2<A, B>> union(
      Chain<? super I, A> a, Chain<? super I, B> b) {
    return unionOf(a, b);
  }

  /**
   * A chain that gives each input to three chains and returns their outputs. Consumes them.
   *
   * @param a first chain
   * @param b second chain
   * @param c third chain
   * @param <I> input type
   * @param <A> output of a
   * @param <B> output of b
   * @param <C> output of c
   * @return the union
   */
  public final <I, A, B, C> Chain<I, Tuple3<A, B, C>> union(
      Chain<? super I, A> a, Chain<? super I, B> b, Chain<? super I, C> c) {
    return unionOf(a, b, c);
  }

  /**
   * A chain that gives each input to four chains and returns their outputs. Consumes them.
   *
   * @param a first chain
   * @param b second chain
   * @param c third chain
   * @param d fourth chain
   * @param <I> input type
   * @param <A> output of a
   * @param <B> output of b
   * @param <C> output of c
   * @param <D> output of d
   * @return the union
   */
  public final <I, A, B, C, D> Chain<I, Tuple4<A, B, C, D>> union(
      Chain<? super I, A> a,
      Chain<? super I, B> b,
      Chain<? super I, C> c,
      Chain<? super I, D> d) {
    return unionOf(a, b, c, d);
  }

  /**
   * A chain that gives each input to five chains and returns their outputs. Consumes them.
   *
   * @param a first chain
   * @param b second chain
   * @param c third chain
   * @param d fourth chain
   * @param e fifth chain
   * @param <I> input type
   * @param <A> output of a
   * @param <B> output of b
   * @param <C> output of c
   * @param <D> output of d
   * @param <E> output of e
   * @return the union
   */
  public final <I, A, B, C, D, E> Chain<I, Tuple5<A, B, C, D, E>> union(
      Chain<? super I, A> a,
      Chain<? super I, B> b,
      Chain<? super I, C> c,
      Chain<? super I, D> d,
      Chain<? super I, E> e) {
    return unionOf(a, b, c, d, e);
  }

  /** A union of 2 to 5 chains; the tuple type follows from the number of parts. */
  private <I, T> Chain<I, T> unionOf(Chain<?, ?>... parts) {
    return declaredChain(recorder -> recorder.union(parts), parts);
  }

  /**
   * A chain that behaves like {@code chain} and also publishes each (non-null) output to
   * {@code events}; make a source of them with {@link #source(EventBlock)}. Consumes the chain.
   *
   * @param chain the chain
   * @param events receives every output
   * @param <I> input type
   * @param <O> output type
   * @return the forked chain
   */
  public final <I, O> Chain<I, O> fork(Chain<I, O> chain, EventBlock<? super O> events) {
    Objects.requireNonNull(events, "events must not be null");
    return declaredChain(recorder -> recorder.fork(chain, events), chain);
  }

  /**
   * A chain that runs {@code chain} only for inputs that pass {@code pass}; the others get
   * {@code substitute}'s output without running the chain. Consumes the chain, which may take a
   * supertype of the input and return a subtype of the output.
   *
   * @param pass decides which inputs run the chain
   * @param chain the guarded chain
   * @param substitute the output for inputs that do not pass
   * @param <I> input type
   * @param <O> output type
   * @return the guarded chain
   */
  public final <I, O> Chain<I, O> guard(
      Predicate<? super I> pass,
      Chain<? super I, ? extends O> chain,
      Block<? super I, ? extends O> substitute) {
    Objects.requireNonNull(pass, "pass predicate must not be null");
    Objects.requireNonNull(substitute, "substitute must not be null");
    return declaredChain(recorder -> recorder.guard(chain, pass, substitute), chain);
  }

  /**
   * Shares one chain between several users without ever running it concurrently. Consumes it.
   *
   * <p>On every media, calls through the users run one at a time in the order they reached the
   * shared chain (first come, first served), so no caller starves. A call waiting for its turn
   * ends, and is not run, when its caller is interrupted (a {@link PrimeException}, the flag kept
   * set) or gives up another way (a call timeout on a media that has one), and with {@link
   * CoreClosedException} when the core closes; the calls behind it keep their order. A call that
   * already runs is not stopped. A block of the shared chain must not call the shared chain
   * (through any user): that call would wait for itself. On every media it fails at once with
   * {@link IllegalStateException}, and the shared chain serves the next call: on Liberty and
   * Radiant wherever the call is made on the caller's thread; on Optimus where it is made on the
   * thread of a service that runs only for the shared chain (its own, a linked chain's each, and
   * those of the chains it consumed: a template's parts, a repeater's chain), in whichever process
   * hosts it. A call made on another thread on its behalf (on Optimus, the service of a chain its
   * block calls through a block it was given, or of another core's chain isolated here) cannot be
   * seen: it waits until its call timeout, an interrupt or {@link #close()} (docs/architecture.md,
   * <i>Errors</i>).
   *
   * <p>On Optimus the shared chain runs as services of its own, each with one host at a time
   * ({@code Hosting.UNORDERED} for any of them is refused at {@link #start()}). The turns are
   * kept by each process for its own users: calls from users in one process never overlap; calls
   * from users in several processes never overlap in a shared chain of one service, but a linked
   * shared chain ({@code a.then(b)}) is several services, so one call may run in {@code b} while
   * another runs in {@code a} (each service still runs one call at a time). Keep the users of a
   * linked stateful chain in one process, or share state only within one chain of the link.
   *
   * @param chain the shared chain
   * @param <I> input type
   * @param <O> output type
   * @return a factory of user chains
   */
  public final <I, O> Isolated<I, O> isolate(Chain<I, O> chain) {
    return declared(
        () -> {
          requireChains(chain);
          return model().isolate(topologyRecorder().isolate(chain), chain);
        },
        chain);
  }

  /**
   * A chain that returns the next value of {@code source} on each call, waiting for one if
   * needed. Its reader is created now, so it sees the values retained now and everything later.
   * A call that gives up while it waits (its thread interrupted, or, on Optimus, its timeout)
   * takes no value with it: the values go to the next calls, in order.
   *
   * @param source the source
   * @param <T> value type
   * @return the collector chain
   */
  public final <T> Chain<Token, T> syncCollector(Source<T> source) {
    requireSource(source);
    return declared(() -> compiled(topologyRecorder().syncCollector(source)));
  }

  /**
   * A chain that returns every value of {@code source} published since its previous call (at
   * the first call: the values retained when the collector was made, and later ones). Never
   * waits.
   *
   * @param source the source
   * @param <T> value type
   * @return the collector chain
   */
  public final <T> Chain<Token, List<T>> asyncCollector(Source<T> source) {
    requireSource(source);
    return declared(() -> compiled(topologyRecorder().asyncCollector(source)));
  }

  /**
   * A chain that runs {@code inner} in a loop until {@code repeater} says stop, and returns its
   * conclusion. Consumes {@code inner}.
   *
   * @param inner runs each round; the first round gets the repeater chain's input
   * @param repeater decides after each round (its {@code collected} list is always empty)
   * @param <I> input type
   * @param <R> output type of the inner chain
   * @param <O> output type: the conclusion
   * @return the repeater chain
   */
  public final <I, R, O> Chain<I, O> repeater(
      Chain<I, R> inner, RepeaterBlock<I, R, Void, O> repeater) {
    Objects.requireNonNull(repeater, "repeater block must not be null");
    return declaredChain(recorder -> recorder.repeater(inner, null, repeater), inner);
  }

  /**
   * A chain that runs {@code inner} in a loop; after each round {@code repeater} sees the
   * round's input and output and the values {@code source} published since the previous round,
   * and says whether to run again or stop with a conclusion. Consumes {@code inner}.
   *
   * @param inner runs each round; the first round gets the repeater chain's input
   * @param source whose values are collected between rounds
   * @param repeater decides after each round
   * @param <I> input type
   * @param <R> output type of the inner chain
   * @param <E> value type of the source
   * @param <O> output type: the conclusion
   * @return the repeater chain
   */
  public final <I, R, E, O> Chain<I, O> repeater(
      Chain<I, R> inner, Source<E> source, RepeaterBlock<I, R, E, O> repeater) {
    Objects.requireNonNull(repeater, "repeater block must not be null");
    requireSource(source);
    return declared(
        () -> {
          requireChains(inner);
          Chain<Token, List<E>> collector = asyncCollector(source);
          return compiled(
              topologyRecorder().repeater(inner, collector.name(), repeater), inner, collector);
        },
        inner);
  }

  // ---------------------------------------------------------------- combinators and timers

  /**
   * A source that pairs every new value of either source with the latest value of the other,
   * once both have one. Values published before every source has one only update the latest;
   * after that each value of either source emits one tuple. A service of this core, named {@code
   * combineLatest(a|b)}; its outputs leave in the order it took its inputs (each source's values
   * in their order). See {@link #zip(Source, Source)} to pair values one to one.
   *
   * @param a first source
   * @param b second source
   * @param <A> values of a
   * @param <B> values of b
   * @return the source of the pairs
   */
  public final <A, B> Source<Tuple2<A, B>> combineLatest(Source<A> a, Source<B> b) {
    return combinators.combineLatest(v -> new Tuple2<>(v[0], v[1]), a, b);
  }

  /**
   * Like {@link #combineLatest(Source, Source)}, for three sources.
   *
   * @param a first source
   * @param b second source
   * @param c third source
   * @param <A> values of a
   * @param <B> values of b
   * @param <C> values of c
   * @return the source of the tuples
   */
  public final <A, B, C> Source<Tuple3<A, B, C>> combineLatest(
      Source<A> a, Source<B> b, Source<C> c) {
    return combinators.combineLatest(v -> new Tuple3<>(v[0], v[1], v[2]), a, b, c);
  }

  /**
   * Like {@link #combineLatest(Source, Source)}, for four sources.
   *
   * @param a first source
   * @param b second source
   * @param c third source
   * @param d fourth source
   * @param <A> values of a
   * @param <B> values of b
   * @param <C> values of c
   * @param <D> values of d
   * @return the source of the tuples
   */
  public final <A, B, C, D> Source<Tuple4<A, B, C, D>> combineLatest(
      Source<A> a, Source<B> b, Source<C> c, Source<D> d) {
    return combinators.combineLatest(v -> new Tuple4<>(v[0], v[1], v[2], v[3]), a, b, c, d);
  }

  /**
   * Like {@link #combineLatest(Source, Source)}, for five sources.
   *
   * @param a first source
   * @param b second source
   * @param c third source
   * @param d fourth source
   * @param e fifth source
   * @param <A> values of a
   * @param <B> values of b
   * @param <C> values of c
   * @param <D> values of d
   * @param <E> values of e
   * @return the source of the tuples
   */
  public final <A, B, C, D, E> Source<Tuple5<A, B, C, D, E>> combineLatest(
      Source<A> a, Source<B> b, Source<C> c, Source<D> d, Source<E> e) {
    return combinators.combineLatest(
        v -> new Tuple5<>(v[0], v[1], v[2], v[3], v[4]), a, b, c, d, e);
  }

  /**
   * A source that pairs the n-th value of {@code a} with the n-th value of {@code b}: one tuple as
   * soon as both have a value not yet paired. A source that runs ahead waits in the zip: each keeps
   * at most {@link CoreConfig#sourceRetention()} unpaired values, and a value that finds its
   * source's buffer full drops that source's oldest unpaired value (logged at WARN, rate-limited),
   * so the pairing is n-th with n-th among the values kept. A service of this core, named {@code
   * zip(a|b)}.
   *
   * @param a first source
   * @param b second source
   * @param <A> values of a
   * @param <B> values of b
   * @return the source of the pairs
   */
  public final <A, B> Source<Tuple2<A, B>> zip(Source<A> a, Source<B> b) {
    return combinators.zip(v -> new Tuple2<>(v[0], v[1]), a, b);
  }

  /**
   * Like {@link #zip(Source, Source)}, for three sources.
   *
   * @param a first source
   * @param b second source
   * @param c third source
   * @param <A> values of a
   * @param <B> values of b
   * @param <C> values of c
   * @return the source of the tuples
   */
  public final <A, B, C> Source<Tuple3<A, B, C>> zip(Source<A> a, Source<B> b, Source<C> c) {
    return combinators.zip(v -> new Tuple3<>(v[0], v[1], v[2]), a, b, c);
  }

  /**
   * Like {@link #zip(Source, Source)}, for four sources.
   *
   * @param a first source
   * @param b second source
   * @param c third source
   * @param d fourth source
   * @param <A> values of a
   * @param <B> values of b
   * @param <C> values of c
   * @param <D> values of d
   * @return the source of the tuples
   */
  public final <A, B, C, D> Source<Tuple4<A, B, C, D>> zip(
      Source<A> a, Source<B> b, Source<C> c, Source<D> d) {
    return combinators.zip(v -> new Tuple4<>(v[0], v[1], v[2], v[3]), a, b, c, d);
  }

  /**
   * Like {@link #zip(Source, Source)}, for five sources.
   *
   * @param a first source
   * @param b second source
   * @param c third source
   * @param d fourth source
   * @param e fifth source
   * @param <A> values of a
   * @param <B> values of b
   * @param <C> values of c
   * @param <D> values of d
   * @param <E> values of e
   * @return the source of the tuples
   */
  public final <A, B, C, D, E> Source<Tuple5<A, B, C, D, E>> zip(
      Source<A> a, Source<B> b, Source<C> c, Source<D> d, Source<E> e) {
    return combinators.zip(v -> new Tuple5<>(v[0], v[1], v[2], v[3], v[4]), a, b, c, d, e);
  }

  /**
   * A source of every value of every one of {@code sources}, as the merge takes them: the values
   * of each source stay in their order; values of different sources interleave as they arrive. A
   * service of this core, named {@code merge(a|b|...)}.
   *
   * @param sources one or more sources of one type
   * @param <T> value type
   * @return the merged source
   */
  @SafeVarargs
  public final <T> Source<T> merge(Source<? extends T>... sources) {
    return combinators.merge(sources);
  }

  /**
   * A source of ticks of the core's clock ({@link CoreConfig#clock()}): tick {@code n} is due
   * {@code n} periods after the core starts (or after this call, on a started core), and is
   * published then with its count and due time. A timer that falls behind (a slow publish, a
   * virtual clock advanced by many periods) publishes every tick that is due, in order, and never
   * drifts. A tick whose publish fails (a full service input, see {@link QueueFullException})
   * goes to the error handler with its count and is not retried. A clock whose {@link
   * PrimeClock#sleepUntil} throws goes to the error handler with the count of the tick it waited
   * for, and the timer asks it again for that tick after a back-off (10 ms doubling up to 1 s).
   * A service of this core: on a media that spreads services over processes only the process that
   * hosts it ticks.
   *
   * @param name the timer's name, unique in this core (like a chain's)
   * @param period the time between two ticks, positive, at most {@code Long.MAX_VALUE}
   *     nanoseconds (about 292 years)
   * @return the source of the ticks
   * @throws IllegalArgumentException if the name is invalid or taken, or the period is not
   *     positive or longer than that
   */
  public final Source<Tick> timer(String name, java.time.Duration period) {
    return combinators.timer(name, period);
  }

  /** The combinators of this core, for {@link Source}'s default methods. */
  final Combinators combinators() {
    return combinators;
  }

  // ---------------------------------------------------------------- sources

  /**
   * Creates a source named {@code source-N} that publishes what {@code events} publishes.
   *
   * @param events the event block
   * @param <T> value type
   * @return a new source
   */
  public final <T> Source<T> source(EventBlock<T> events) {
    Objects.requireNonNull(events, "events must not be null");
    ensureOpen();
    return declared(() -> model().eventSource(topologyRecorder().eventSource(null, events), events));
  }

  /**
   * Creates a named source that publishes what {@code events} publishes.
   *
   * @param name unique in this core
   * @param events the event block
   * @param <T> value type
   * @return a new source
   */
  public final <T> Source<T> source(String name, EventBlock<T> events) {
    Objects.requireNonNull(name, "name must not be null");
    Objects.requireNonNull(events, "events must not be null");
    ensureOpen();
    return declared(() -> model().eventSource(topologyRecorder().eventSource(name, events), events));
  }

  /**
   * Creates a named source with a pseudoname (see {@link #chain(String, String, Block)}).
   *
   * @param name unique in this core
   * @param pseudoname 1 to 120 characters, not only whitespace, no control characters
   * @param events the event block
   * @param <T> value type
   * @return a new source
   * @throws IllegalArgumentException if the name is invalid or taken or the pseudoname invalid
   */
  public final <T> Source<T> source(String name, String pseudoname, EventBlock<T> events) {
    Objects.requireNonNull(name, "name must not be null");
    Objects.requireNonNull(events, "events must not be null");
    TopologyRecorder.checkPseudoname(pseudoname);
    ensureOpen();
    return declared(
        () ->
            model()
                .eventSource(
                    Pseudonames.record(topologyRecorder(), name, pseudoname, events), events));
  }

  /**
   * Runs {@code chain} on every value of {@code source} as one service, consuming the chain.
   * The chain may take any supertype of the source's values. Values the chain maps to {@code
   * null} are not published. On a source of the media's own ({@link SourceCompiler}) the media
   * compiles the service; otherwise it runs on a thread of this core and publishes to an in-memory
   * source.
   *
   * <p>A link that fails leaves the chain unused; it can be made again (as {@link
   * Chain#toBlock()} says).
   *
   * @param source the input source (may belong to another core)
   * @param chain the chain
   * @param <I> input type
   * @param <O> output type
   * @return the source of outputs, named {@code source>chain}
   */
  public final <I, O> Source<O> link(Source<I> source, Chain<? super I, O> chain) {
    requireSource(source);
    return declared(
        () -> {
          requireChains(chain);
          return model().service(topologyRecorder().sourceLink(source, chain), source, chain);
        },
        chain);
  }

  /**
   * {@link Source#then(Block)}: links {@code source} to a new chain made of {@code block}, in one
   * declaration, so that a link that is refused leaves no chain of the block behind.
   */
  final <I, O> Source<O> linkBlock(Source<I> source, Block<? super I, ? extends O> block) {
    return declared(() -> link(source, chain(Block.<I, O>narrow(block))));
  }

  /**
   * {@link Source#filter}: a service that republishes the values that pass (compiled like {@link
   * #link(Source, Chain)}).
   *
   * @param source the source
   * @param predicate decides
   * @param <T> value type
   * @return the filtered source
   */
  final <T> Source<T> filterSource(Source<T> source, Predicate<? super T> predicate) {
    requireSource(source);
    Objects.requireNonNull(predicate, "predicate must not be null");
    return declared(
        () -> model().service(topologyRecorder().filter(source, predicate), source, null));
  }

  /**
   * {@link Source#flatMap}: a service that publishes every value made of each (compiled like
   * {@link #link(Source, Chain)}).
   *
   * @param source the source
   * @param block makes the values
   * @param <T> input type
   * @param <R> output type
   * @return the flattened source
   */
  final <T, R> Source<R> flatMapSource(
      Source<T> source, Block<? super T, ? extends Iterable<? extends R>> block) {
    requireSource(source);
    Objects.requireNonNull(block, "block must not be null");
    return declared(
        () -> model().service(topologyRecorder().flatMap(source, block), source, null));
  }

  /**
   * {@link Source#listen}: a service that calls the listener with each value (compiled like
   * {@link #link(Source, Chain)}).
   *
   * @param source the source
   * @param listener the listener
   * @param <T> value type
   */
  final <T> void listenSource(Source<T> source, Consumer<? super T> listener) {
    requireSource(source);
    Objects.requireNonNull(listener, "listener must not be null");
    declared(
        () -> {
          model().service(topologyRecorder().listener(source, listener), source, null);
          return null;
        });
  }

  /**
   * Declares a generic service: a long-running service fed by no source, such as a hardware driver
   * or a poller, that {@linkplain GenericService#initialize() initializes} once and then
   * {@linkplain GenericService#work() works} over and over on a thread of its own. It runs from
   * {@link #start()} (at once if the core is started) until {@link #close()}, which interrupts it
   * and waits for its {@link GenericService#shutdown() shutdown} within {@link
   * CoreConfig#shutdownTimeout()}. Its failures go to the {@link ErrorHandler} under {@code name},
   * with the {@link GenericService.Step} that failed as the input; see {@link GenericService} for
   * the whole contract. It is a service of the {@linkplain #topology() topology}; a media that
   * spreads services over processes runs it only in the process that hosts it.
   *
   * @param name unique in this core; 1 to 200 characters, no whitespace or braces
   * @param service the service
   * @throws IllegalArgumentException if the name is invalid or taken
   * @throws CoreClosedException if the core is closed
   */
  public final void service(String name, GenericService service) {
    Objects.requireNonNull(name, "name must not be null");
    Objects.requireNonNull(service, "service must not be null");
    ensureOpen();
    declared(
        () -> {
          String claimed = topologyRecorder().genericService(name, service);
          runGenericService(claimed, model().genericService(claimed, service));
          return null;
        });
  }

  /**
   * Runs a generic service, whose name is already claimed: by default on a thread of this core
   * (started with the other services), through {@link dev.prime.GenericServiceLoop}. A media
   * that spreads services over processes overrides it to run the service only where it is hosted.
   *
   * @param name the service's name
   * @param service the service
   */
  protected void runGenericService(String name, GenericService service) {
    inProcess.generic(name, service);
  }

  /**
   * The services of this core's diagram that this process runs, in declaration order: every
   * chain made of a block, every template chain, every filter, flat-map and listener, and every
   * combinator, timer and generic service (see {@link dev.prime.topology.TopologyNode}); linked
   * chains and sources are not services. The
   * same declarations give the same names on every media; a media that spreads services over
   * processes (Optimus) leaves out those hosted elsewhere. Like {@link #topology()}, it never
   * waits for a declaration under way on another thread.
   *
   * @return a snapshot
   */
  public final Set<String> serviceNames() {
    return topologyRecorder().hostedServices(this::isHostedHere);
  }

  /**
   * The diagram declared on this core so far, as data: chains, sources, links, templates,
   * services, readers and where each service is hosted. The same declarations give an equal
   * topology, and the same Mermaid and DOT drawings, on every media.
   *
   * <p>It never waits for a declaration under way on another thread (one that waits for another
   * process, or a slow compilation): it shows every declaration that finished, and nothing of one
   * under way, which may still fail and leave nothing. So an inspector, metrics or a monitoring
   * thread reading it is never held up by a declaration.
   *
   * @return an immutable snapshot
   */
  public final Topology topology() {
    return topologyRecorder().snapshot(this::isHostedHere);
  }

  /**
   * What this core recorded: every value its sources published and its chains made of a block
   * returned, with time stamps (see {@link Recording}). On Optimus, what this process published
   * and the chains it hosts returned.
   *
   * @return the recording, the same object on every call
   * @throws IllegalStateException if recording is off ({@link CoreConfig.Builder#recording})
   */
  public final Recording recording() {
    return model().recording();
  }

  /**
   * This core's metrics: values in and out, failures, dead letters, queue depth, missed values
   * and processing times of every chain, service and event source of its diagram that runs logic,
   * named as in the {@linkplain #topology() topology} (see {@link Metrics}). On Optimus, what this
   * process hosts.
   *
   * @return the metrics, the same object on every call
   * @throws IllegalStateException if metrics are off ({@link CoreConfig.Builder#metrics})
   */
  public final Metrics metrics() {
    return model().metrics();
  }

  /** {@return the media's short name this core was created with ({@code liberty}, ...)} */
  final String mediaName() {
    return media;
  }

  /**
   * Whether this process runs a service of the diagram. Every media that runs in one process
   * hosts all of them; a media that spreads services over processes overrides this.
   *
   * @param service a service's name
   * @return true by default
   */
  protected boolean isHostedHere(String service) {
    return true;
  }

  /**
   * Called when a combinator of sources or a timer, which runs on this core's own threads, is
   * declared on a started core, before its threads start: a media that spreads services over
   * processes overrides it to take the service's hosting as {@code start()} takes it for those
   * declared before (Optimus: it claims the host lease), so that one process at a time runs it.
   * Nothing by default.
   *
   * @param service the combinator's or timer's name in the diagram
   * @throws IllegalStateException if another process hosts it; the declaration then fails
   */
  protected void hostOnCoreThreads(String service) {}

  /**
   * Called when the declaration of a combinator or timer for which {@link #hostOnCoreThreads}
   * returned failed after it (an input's reader could not be opened, for instance): a media gives
   * up the hosting it took for it (Optimus: releases the host lease), so that the failed
   * declaration leaves nothing behind and can be made again. Nothing by default. Must not throw.
   *
   * @param service the combinator's or timer's name in the diagram
   */
  protected void unhostOnCoreThreads(String service) {}

  /**
   * Whether the caller of the call this thread runs a block for has given up on it (it was
   * interrupted, or its timeout passed). Called on a service's thread while a block waits for an
   * {@linkplain #isolate isolated chain}, about every 50 ms, and once when its turn comes after a
   * wait: a call its caller gave up is then not run. A media whose blocks run on the caller's own
   * thread needs nothing here (an interrupt of that thread ends the wait); a media that runs
   * calls on service threads overrides this. Must not throw; when it cannot tell, it answers
   * false.
   *
   * @return false by default
   */
  protected boolean callerGaveUp() {
    return false;
  }

  /**
   * Records a reader the program opened on one of this core's sources of the media's own ({@link
   * SourceCompiler}) in the {@linkplain #topology() topology} (the core records the readers of
   * its in-memory sources itself).
   *
   * @param source the source's name
   */
  protected final void recordReader(String source) {
    topologyRecorder().reader(source);
  }

  /**
   * Tells the core that the media published {@code values} to its event source {@code source} in
   * one step, not through the source's event block (Optimus: {@code publishAll}), so that they
   * are recorded and metered as what the event block publishes is: with recording on, each
   * accepted value is recorded under the source, in order, stamped with the time the publish
   * began; with metrics on, each value counts in, and, if accepted, out, timed with the whole
   * publish. Call it once the publish has returned ({@code accepted}) or failed. Nothing happens
   * for a name that is not an event source of this core, or with recording and metrics off.
   *
   * @param source the event source's name
   * @param values the values, in the order they were published
   * @param wallTime the wall-clock time the publish began
   * @param monotonicNanos {@link System#nanoTime()} when the publish began
   * @param accepted whether the media accepted the values (a refused publish published nothing)
   */
  protected final void publishedTogether(
      String source,
      List<?> values,
      java.time.Instant wallTime,
      long monotonicNanos,
      boolean accepted) {
    Objects.requireNonNull(source, "source must not be null");
    Objects.requireNonNull(values, "values must not be null");
    Objects.requireNonNull(wallTime, "wallTime must not be null");
    model().publishedTogether(source, values, wallTime, monotonicNanos, accepted);
  }

  /** Where this core's diagram is recorded and every name is made. */
  final TopologyRecorder topologyRecorder() {
    return recorder;
  }

  // ---------------------------------------------------------------- lifecycle

  /**
   * Starts the services declared so far; services declared later start at once. A declaration
   * under way on another thread when {@code start()} is called ends first: its services start
   * with the others (on Optimus, {@code start()} also claims its host leases).
   *
   * <p>A {@code start()} that throws (on Optimus: a Redis that refuses what the core needs, a
   * hosting it may not take, a wait for Redis interrupted; Liberty and Radiant have no such
   * failure) leaves the core <em>failed to start</em>, on every media: it may have launched part
   * of its services, and it runs nothing more. A second {@code start()} and every declaration
   * (a chain, a source, {@link Chain#toBlock()}, a link, a template, a combinator, a timer, a
   * generic service) then throw an {@link IllegalStateException} that says {@code start()} failed,
   * quotes its message, carries what it threw as its cause, and says to close the core and make a
   * new one. Everything else is as on a core that was not started ({@link #isStarted()} is true,
   * as for any start that was accepted): services it did not launch never run, and no {@link
   * #whenRunning} hook starts (each {@code onClose} runs at {@code close()}). {@link #close()} works as on any core and releases
   * everything the partial start took (threads, connections and, on Optimus, the core's leases
   * and seats in Redis).
   *
   * @throws IllegalStateException if the core was already started, or its start failed
   * @throws CoreClosedException if the core is closed
   */
  public final void start() {
    synchronized (lifecycle) {
      refuseStart(); // at once, not after a declaration under way (one may wait for Redis)
    }
    // a declaration under way on another thread ends first: it left what it made to this start
    // (it saw the core not started), which must then see it, though topology() would not
    synchronized (recorder) {
      synchronized (lifecycle) {
        refuseStart();
        state = State.STARTED;
        started = true;
      }
    }
    try {
      onStart();
    } catch (Throwable e) { // also a checked exception, which a media in Kotlin can throw
      synchronized (lifecycle) {
        startFailure = e;
        if (state == State.STARTED) { // not if a close() came meanwhile
          state = State.FAILED;
        }
      }
      throw e;
    }
    combinators.started();
    services.startAll();
    hooks.started();
    LifecycleHooks.logStarted(this, media, startDetails(), serviceNames());
  }

  /** Throws what {@link #start()} throws on a core that is not new; call holding {@code lifecycle}. */
  private void refuseStart() {
    if (state == State.CLOSED) {
      throw new CoreClosedException(name);
    }
    if (state == State.FAILED) {
      throw startFailed("a second start()");
    }
    if (state == State.STARTED) {
      throw new IllegalStateException(
          "core '" + name + "' is already started; call start() once per core");
    }
  }

  /**
   * {@return what the start line logged by {@link #start()} adds after the media's name, such as
   * {@code " with Redis redis://127.0.0.1:6379"}; never a password; empty by default}
   */
  protected String startDetails() {
    return "";
  }

  /**
   * Stops every service, waiting at most {@link CoreConfig#shutdownTimeout()} for them, and
   * releases the core's threads and connections. Idempotent. It first closes the {@link
   * #whenRunning} hooks, waiting (at most {@code shutdownTimeout}) for an {@code onStart} under way
   * on another thread to return before running its {@code onClose}.
   *
   * <p>A {@code close()} that finds another under way on another thread waits until that one has
   * finished (at most three times {@code shutdownTimeout} plus 30 s), so a shutdown hook that
   * closes a core the program is closing does not let the JVM exit half-way through. It returns
   * at once when called from one of the core's own threads (a service, a listener), which the
   * first close may be waiting for, or from within the first close (an {@code onClose} of {@link
   * #whenRunning}); an interrupt ends its wait and stays set.
   */
  @Override
  public final void close() {
    boolean first;
    synchronized (lifecycle) {
      first = state != State.CLOSED;
      if (first) {
        state = State.CLOSED;
        closingThread = Thread.currentThread();
      }
    }
    if (!first) {
      awaitClosed();
      return;
    }
    try {
      hooks.closing();
      inProcess.close();
      services.stopAll(config.shutdownTimeout());
      onClose();
      combinators.closed();
      ModelCompiler<?> declared = compiler;
      if (declared != null) {
        declared.closed();
      }
      config.flushErrorSummaries();
    } finally {
      closed.countDown();
    }
  }

  /** A second {@code close()}: waits for the first, unless that could wait for this thread. */
  private void awaitClosed() {
    Thread current = Thread.currentThread();
    if (closed.getCount() == 0 || current == closingThread || isOwnThread(current)) {
      return;
    }
    long shutdownMillis =
        TimeUnit.NANOSECONDS.toMillis(Deadlines.boundedNanos(config.shutdownTimeout()));
    // the first close may wait a shutdownTimeout for a hook's start, then for services and media
    long bound = 3 * shutdownMillis + CLOSE_WAIT_SLACK_MILLIS;
    try {
      if (!closed.await(bound, TimeUnit.MILLISECONDS)) {
        LOG.warn(
            "core '{}': close() waited {} ms for the close under way on thread {}, which has not"
                + " finished; returning",
            name,
            bound,
            closingThread.getName());
      }
    } catch (InterruptedException e) {
      current.interrupt();
    }
  }

  /**
   * Whether {@code thread} is one of this core's own threads (one a service runs on), which the
   * close under way may be waiting for: a {@code close()} from it returns at once instead of
   * waiting for that close. A media whose services run on threads of its own adds those.
   *
   * @param thread a thread
   * @return whether the core runs services on it
   */
  protected boolean isOwnThread(Thread thread) {
    return services.isServiceThread(thread);
  }

  /**
   * Ties work that runs beside the diagram to this core's lifecycle, such as a Kotlin flow that
   * feeds a source: {@code onStart} runs when the core starts, after its services (at once, on
   * the calling thread, if the core has started), and {@code onClose} once when it closes, before
   * its sources close (also if it never started). Both must return quickly; an exception from
   * either goes to the error handler under {@code name}, with {@code "start"} or {@code "close"}
   * as the input; a handler that throws is logged and ignored ({@link ErrorHandler}), so {@code
   * start()} and {@code close()} carry on whole.
   *
   * <p>{@code onClose} always runs after {@code onStart} if that ran, whatever the interleaving:
   * a {@code close()} that comes while {@code onStart} runs on another thread (in {@code start()},
   * or in this call on a started core) waits for it to return, at most {@link
   * CoreConfig#shutdownTimeout()}, then runs {@code onClose}, so that what {@code onStart} made
   * (a metrics binder's meters) is gone when {@code close()} returns; a hook not yet started when
   * the core closes never starts. A {@code close()} that cannot wait (called from {@code onStart}
   * itself or from one of the core's own threads, interrupted, or past that bound) leaves {@code
   * onClose} to the thread running {@code onStart}, which runs it as soon as {@code onStart}
   * returns.
   *
   * @param name names the work in the error handler, such as the source it feeds
   * @param onStart starts the work
   * @param onClose stops it; runs once, after {@code onStart} if that ran
   * @throws CoreClosedException if the core is closed
   */
  public final void whenRunning(String name, Runnable onStart, Runnable onClose) {
    hooks.add(name, onStart, onClose);
  }

  /** Called by {@link #start()} before the in-process services start. */
  protected void onStart() {}

  /** Called once by {@link #close()} after the in-process services stopped. */
  protected void onClose() {}

  @Override
  public String toString() {
    return getClass().getSimpleName() + "[" + name + ", " + state + "]";
  }

  // ---------------------------------------------------------------- for media

  /**
   * Throws if the core is closed.
   *
   * @throws CoreClosedException if it is
   */
  protected final void ensureOpen() {
    if (state == State.CLOSED) {
      throw new CoreClosedException(name);
    }
  }

  /**
   * Throws if {@link #start()} failed: a core that failed to start runs nothing more, so it
   * refuses {@code what} (every declaration, and on a media that refuses such use before {@code
   * start()}, a publish, a call or a read).
   *
   * @param what what is refused, such as {@code "a declaration"}
   * @throws IllegalStateException if it failed, saying so, quoting the failure (its cause)
   */
  protected final void ensureStartDidNotFail(String what) {
    if (state == State.FAILED) {
      throw startFailed(what);
    }
  }

  private IllegalStateException startFailed(String what) {
    Throwable failure = startFailure;
    return new IllegalStateException(
        "core '"
            + name
            + "' failed to start (start() threw "
            + failure
            + "), so "
            + what
            + " is refused: a core whose start() failed runs nothing more and takes no"
            + " declaration and no second start(); close() it, which releases what the failed"
            + " start took, and make a new core",
        failure);
  }

  /** Checks chains given to a declaration before it consumes any ({@link DeclarationChecks}). */
  final void requireChains(Chain<?, ?>... chains) {
    DeclarationChecks.requireChains(this, chains);
  }

  /** Checks a source given to a declaration ({@link DeclarationChecks}). */
  final void requireSource(Source<?> source) {
    DeclarationChecks.requireSource(this, source);
  }
}

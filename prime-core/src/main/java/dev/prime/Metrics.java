package dev.prime;

import dev.prime.internal.RateLimitedLog;
import dev.prime.topology.TopologyNode;
import java.util.ArrayList;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.Objects;
import java.util.function.Predicate;

/**
 * A core's metrics: for every metered node of its diagram, how many values went in and out, how
 * many failed, the media's dead letters, queue depth and missed values, and how long each value
 * took. Get it with {@link PrimeCore#metrics()} from a core whose {@link CoreConfig} turns metrics
 * on ({@link CoreConfig.Builder#metrics(boolean)}); read it as immutable snapshots ({@link
 * #services()}, {@link #service(String)}).
 *
 * <p>Metered nodes, named as in the topology model ({@link PrimeCore#topology()}), so the same
 * declarations give the same names on every media:
 *
 * <ul>
 *   <li>every chain that runs logic: made of a block ({@code BlockChain}), another core's chain
 *       ({@code ForeignChain}), and every template chain ({@code IfElse}, {@code ForEach}, {@code
 *       Union}, {@code Fork}, {@code Guard}, {@code IsolatedUser}, {@code SyncCollector}, {@code
 *       AsyncCollector}, {@code Repeater}): in = calls, out = non-null results, failures = calls
 *       that threw, processing = the time of each call (a template's includes its parts'). Linked
 *       chains ({@code Link}) are not metered: their parts are;
 *   <li>every service of a source that runs a function ({@code Filter}, {@code FlatMap}, {@code
 *       Listener}): in = values taken, out = values passed or made (a listener's is 0), failures =
 *       values its function threw on. A chain linked to a source is metered as its chains;
 *   <li>every source fed by an event block ({@code EventSource}): in = publishes, out = publishes
 *       the media accepted (the difference: publishes it refused, such as a {@link
 *       QueueFullException}), processing = how long the media took to accept each;
 *   <li>every generic service ({@code GenericServiceNode}, {@link PrimeCore#service(String,
 *       GenericService)}): in = calls of {@link GenericService#work()}, out = calls that returned,
 *       failures = calls that threw (but for a call ended because the service stops, which the
 *       error handler is not told of either), processing = the time of each call (a {@code work}
 *       that waits for its next piece of work counts its wait);
 *   <li>every combinator ({@code Combinator}: {@code combineLatest}, {@code zip}, {@code merge},
 *       {@code withLatestFrom}, {@code sample}): in = values it took from its inputs, out = values
 *       it published that the media accepted (tuples, merged or sampled values), failures = input
 *       values whose step threw, processing = the time of each input value's step (its publish
 *       included);
 *   <li>every timer ({@code Timer}, {@link PrimeCore#timer}): in = ticks published, out = ticks
 *       the media accepted, processing = how long the media took to accept each.
 * </ul>
 *
 * Where a media has them, {@link ServiceMetrics#deadLetters()} (Optimus), {@link
 * ServiceMetrics#queueDepth()} (a filter's, flat-map's or listener's input on every media, each
 * Optimus service's lists) and {@link ServiceMetrics#missed()} (what the plain readers of an
 * event source, a combinator or a timer missed) are read when a snapshot
 * is taken.
 *
 * <p>Cost and threads. When metrics are off nothing is compiled into any chain, service or
 * source. When on, each value a metered node processes costs two {@link System#nanoTime()} reads
 * and a few uncontended atomic additions on the thread that processes it (contended additions
 * spread over cells, as {@link java.util.concurrent.atomic.LongAdder}'s do), plus the calls to
 * its {@linkplain #onProcessed listeners}. A snapshot reads those counters without stopping the
 * services (see {@link ServiceMetrics} for what that means) and, on Optimus, asks Redis for the
 * queue depths and dead-letter counts (a few round trips per service): take snapshots now and
 * then (a page refreshing every second), not per value.
 *
 * <p>Thread-safe; the same object on every call of {@link PrimeCore#metrics()}.
 */
public final class Metrics {
  private final String core;
  private final String media;
  private final TopologyRecorder model;
  private final ServiceGauges gauges; // the media's, or null
  private final Predicate<String> hostedHere;
  private final Map<String, ServiceMeter> meters = new LinkedHashMap<>(); // guarded by itself
  private final RateLimitedLog listenerFailures =
      new RateLimitedLog(ProcessingListener.class.getName()); // keyed by node; flushed at close

  Metrics(
      String core,
      String media,
      TopologyRecorder model,
      ServiceGauges gauges,
      Predicate<String> hostedHere) {
    this.core = core;
    this.media = media;
    this.model = model;
    this.gauges = gauges;
    this.hostedHere = hostedHere;
  }

  /** {@return the core's name} */
  public String core() {
    return core;
  }

  /**
   * {@return the media's short name: {@code liberty}, {@code radiant}, {@code optimus} (the name
   * its core was created with)}
   */
  public String media() {
    return media;
  }

  /**
   * {@return the names of the metered nodes, in declaration order} On a media that spreads
   * services over processes (Optimus), the services this process hosts and every event source.
   */
  public List<String> names() {
    List<String> names = new ArrayList<>();
    for (ServiceMeter meter : meters()) {
      names.add(meter.name());
    }
    return List.copyOf(names);
  }

  /** {@return a snapshot of every metered node, in declaration order} */
  public List<ServiceMetrics> services() {
    List<ServiceMetrics> all = new ArrayList<>();
    for (ServiceMeter meter : meters()) {
      all.add(snapshot(meter));
    }
    return List.copyOf(all);
  }

  /**
   * A snapshot of one metered node.
   *
   * @param name its name in the topology model
   * @return its metrics now
   * @throws IllegalArgumentException if no metered node has that name (the message lists those
   *     that have)
   */
  public ServiceMetrics service(String name) {
    return snapshot(meter(name));
  }

  /**
   * Whether a metered node has an input queue on this media, so that {@link
   * ServiceMetrics#queueDepth()} of its snapshots is a count whenever the media can read it: a
   * filter's, flat-map's or listener's input on every media, and the input of every service of a
   * chain on Optimus; never a generic service, combinator or timer, on any media.
   * It does not depend on reading the queue, so it tells a node without a queue (always {@code
   * -1}) from a queue that cannot be read now (Optimus while Redis is unreachable).
   *
   * @param name its name in the topology model
   * @return whether it has a queue
   * @throws IllegalArgumentException if no metered node has that name (the message lists those
   *     that have)
   */
  public boolean hasQueue(String name) {
    ServiceMeter meter = meter(name);
    if (meter.queueDepth() >= 0) {
      return true; // an input queue of the core's own
    }
    return gauges != null && !meter.isSource() && !meter.runByCore() && gauges.hasQueue(name);
  }

  /**
   * Calls {@code listener} with the time of every value the node {@code service} processes from
   * now on, on the thread that processed it (see {@link ProcessingListener}). A metrics library
   * that keeps its own histogram registers one per node.
   *
   * @param service a metered node's name
   * @param listener told of each value
   * @return closing it stops the calls
   * @throws IllegalArgumentException if no metered node has that name
   */
  public Subscription onProcessed(String service, ProcessingListener listener) {
    Objects.requireNonNull(listener, "listener must not be null");
    ServiceMeter meter = meter(service);
    meter.addListener(listener);
    return () -> meter.removeListener(listener);
  }

  /** A registration that can be undone. */
  @FunctionalInterface
  public interface Subscription extends AutoCloseable {
    /** Undoes it; closing twice does nothing more. */
    @Override
    void close();
  }

  /** {@return where the meters log their listeners' failures} */
  RateLimitedLog listenerFailures() {
    return listenerFailures;
  }

  /** The core closed: writes the count of listener failures still owed to the log. */
  void closed() {
    listenerFailures.flush();
  }

  /** {@return the meter registered under {@code name}, or {@code null}} */
  ServiceMeter registered(String name) {
    synchronized (meters) {
      return meters.get(name);
    }
  }

  /** Registers the meter of a node being compiled (replacing one a failed declaration left). */
  void add(ServiceMeter meter) {
    synchronized (meters) {
      meters.put(meter.name(), meter);
    }
  }

  private ServiceMeter meter(String name) {
    Objects.requireNonNull(name, "name must not be null");
    ServiceMeter meter;
    synchronized (meters) {
      meter = meters.get(name);
    }
    if (meter == null || !declared(name)) {
      throw new IllegalArgumentException(
          "no metered node is named '" + name + "' in core '" + core + "': the metered names"
              + " (chains that run logic, filters, flat-maps, listeners, event sources, generic"
              + " services, combinators and timers) are "
              + names());
    }
    return meter;
  }

  /**
   * The meters of nodes still in the model (a failed declaration forgets its nodes) that this
   * process runs.
   */
  private List<ServiceMeter> meters() {
    List<ServiceMeter> all;
    synchronized (meters) {
      all = new ArrayList<>(meters.values());
    }
    all.removeIf(meter -> !declared(meter.name()));
    return all;
  }

  private boolean declared(String name) {
    TopologyNode node;
    try {
      node = model.node(name);
    } catch (IllegalArgumentException forgotten) {
      return false;
    }
    return node instanceof TopologyNode.EventSource || hostedHere.test(name);
  }

  private ServiceMetrics snapshot(ServiceMeter meter) {
    String name = meter.name();
    long depth = meter.queueDepth();
    long deadLetters = 0;
    long missed = meter.missed();
    if (gauges != null && meter.isSource()) { // a source has neither queue nor dead letters
      missed += gauges.missed(name);
    } else if (gauges != null && !meter.runByCore()) { // nor has a generic service
      if (depth < 0) {
        depth = gauges.queueDepth(name);
      }
      deadLetters = gauges.deadLetters(name);
    }
    return meter.snapshot(model.pseudoname(name), deadLetters, depth, missed);
  }

  @Override
  public String toString() {
    return "Metrics[" + core + " (" + media + "), " + names().size() + " metered nodes]";
  }
}

package dev.prime.metrics;

import dev.prime.CoreConfig;
import dev.prime.Metrics;
import dev.prime.PrimeCore;
import dev.prime.ServiceMetrics;
import dev.prime.topology.TopologyNode;
import io.micrometer.core.instrument.FunctionCounter;
import io.micrometer.core.instrument.Gauge;
import io.micrometer.core.instrument.Meter;
import io.micrometer.core.instrument.MeterRegistry;
import io.micrometer.core.instrument.Tags;
import io.micrometer.core.instrument.Timer;
import io.micrometer.core.instrument.binder.MeterBinder;
import java.time.Duration;
import java.util.ArrayList;
import java.util.Collections;
import java.util.HashSet;
import java.util.IdentityHashMap;
import java.util.List;
import java.util.Map;
import java.util.Objects;
import java.util.Set;
import java.util.concurrent.TimeUnit;
import java.util.function.ToDoubleFunction;

/**
 * Binds a core's {@link Metrics} to a Micrometer {@link MeterRegistry}: for every metered node of
 * its diagram (see {@link Metrics} for which they are), the meters below, tagged {@code service}
 * (the node's name in the topology), {@code kind} (its kind: {@code BlockChain}, {@code Filter},
 * {@code EventSource}, ...), {@code media} ({@code liberty}, {@code radiant}, {@code optimus}) and
 * {@code core} (the core's name). The names come from the topology model, so the same diagram
 * gives the same meters on every media.
 *
 * <table>
 *   <caption>Meters per metered node</caption>
 *   <tr><th>name</th><th>type</th><th>what</th></tr>
 *   <tr><td>{@value #VALUES_IN}</td><td>function counter</td>
 *       <td>{@link ServiceMetrics#valuesIn()}</td></tr>
 *   <tr><td>{@value #VALUES_OUT}</td><td>function counter</td>
 *       <td>{@link ServiceMetrics#valuesOut()}</td></tr>
 *   <tr><td>{@value #FAILURES}</td><td>function counter</td>
 *       <td>{@link ServiceMetrics#failures()}</td></tr>
 *   <tr><td>{@value #MISSED}</td><td>function counter</td>
 *       <td>{@link ServiceMetrics#missed()}</td></tr>
 *   <tr><td>{@value #DEAD_LETTERS}</td><td>gauge</td>
 *       <td>{@link ServiceMetrics#deadLetters()} (a gauge: clearing an Optimus service's dead
 *       letters lowers it)</td></tr>
 *   <tr><td>{@value #QUEUE_DEPTH}</td><td>gauge</td>
 *       <td>{@link ServiceMetrics#queueDepth()}; only for nodes with a queue ({@link
 *       dev.prime.Metrics#hasQueue}), also when bound while the media cannot read it (NaN while
 *       it cannot)</td></tr>
 *   <tr><td>{@value #PROCESSING}</td><td>timer with a percentile histogram</td>
 *       <td>the time of every value processed after binding, recorded by a {@link
 *       dev.prime.ProcessingListener} on the thread that processed it</td></tr>
 * </table>
 *
 * <pre>{@code
 * PrimeCore core = new LibertyCore(CoreConfig.builder().metrics(true).build());
 * ... // declare the diagram
 * PrimeMetrics.of(core).bindTo(registry);   // or registry.config().meterFilter(...) first
 * core.start();
 * }</pre>
 *
 * <p>Bind once the diagram is declared (before or after {@link PrimeCore#start()}): nodes
 * declared later get no meters. A service declared by then that this process does not run then
 * (on Optimus, one another process runs, such as one this process stands by for) gets its meters
 * at a read of the binder's meters once this process runs it. The counters and gauges read the
 * core's metrics when the registry asks, from one snapshot of all nodes kept for {@linkplain
 * #of(PrimeCore, Duration) a refresh period} (1 s by default), so that a registry reading every
 * meter of a large diagram takes one snapshot, not one per meter (on Optimus a snapshot asks
 * Redis for queue depths and dead letters). The meters of a node this process does not run now
 * (on Optimus, a service another process runs, such as one this process stands by for) read NaN,
 * from the same snapshot. {@link #close()} removes the meters and stops the timers' recording.
 *
 * <p>Thread-safe. The per-value cost with metrics on is the core's (see {@link Metrics}) plus one
 * {@link Timer#record(long, TimeUnit)} per value and bound registry.
 */
public final class PrimeMetrics implements MeterBinder, AutoCloseable {
  /** Values given to a node: {@link ServiceMetrics#valuesIn()}. */
  public static final String VALUES_IN = "prime.service.values.in";

  /** Values a node gave out: {@link ServiceMetrics#valuesOut()}. */
  public static final String VALUES_OUT = "prime.service.values.out";

  /** Values on which a node's logic threw: {@link ServiceMetrics#failures()}. */
  public static final String FAILURES = "prime.service.failures";

  /** Values a node's input missed: {@link ServiceMetrics#missed()}. */
  public static final String MISSED = "prime.service.missed";

  /** Values the media set aside as dead letters: {@link ServiceMetrics#deadLetters()}. */
  public static final String DEAD_LETTERS = "prime.service.dead.letters";

  /** Values in a node's input not finished: {@link ServiceMetrics#queueDepth()}. */
  public static final String QUEUE_DEPTH = "prime.service.queue.depth";

  /** The time per value: {@link ServiceMetrics#processing()}, as a timer. */
  public static final String PROCESSING = "prime.service.processing";

  /** The default time a snapshot serves the registry's reads. */
  public static final Duration DEFAULT_REFRESH = Duration.ofSeconds(1);

  private final PrimeCore core;
  private final Metrics metrics;
  private final SnapshotCache snapshots;
  private final List<Bound> bound = new ArrayList<>(); // guarded by this
  /** Per bound registry, the nodes declared at binding that this process did not run then. */
  private final Map<MeterRegistry, Set<String>> awaited = new IdentityHashMap<>(); // by this
  private volatile long checkedAt = -1; // the snapshot generation bindNewlyRun last checked

  private PrimeMetrics(PrimeCore core, Duration refresh) {
    this.core = Objects.requireNonNull(core, "core must not be null");
    this.metrics = metricsOf(core);
    this.snapshots = new SnapshotCache(metrics, refresh);
  }

  /**
   * A binder of {@code core}'s metrics, reading a snapshot at most every {@link
   * #DEFAULT_REFRESH}.
   *
   * @param core a core whose metrics are on ({@link CoreConfig.Builder#metrics(boolean)})
   * @return the binder; {@link #bindTo(MeterRegistry)} registers the meters
   * @throws IllegalStateException if the core's metrics are off (the message says how to turn
   *     them on)
   */
  public static PrimeMetrics of(PrimeCore core) {
    return of(core, DEFAULT_REFRESH);
  }

  /**
   * A binder of {@code core}'s metrics, reading a snapshot at most every {@code refresh}.
   *
   * @param core a core whose metrics are on
   * @param refresh how long one snapshot serves the registry's reads; {@link Duration#ZERO}: a
   *     fresh snapshot of the node on every read (exact, costlier on Optimus); one of {@code
   *     Long.MAX_VALUE} nanoseconds (about 292 years) or longer serves the first snapshot for as
   *     long as the binder is bound
   * @return the binder
   * @throws IllegalStateException if the core's metrics are off
   * @throws IllegalArgumentException if {@code refresh} is negative
   */
  public static PrimeMetrics of(PrimeCore core, Duration refresh) {
    return new PrimeMetrics(core, refresh);
  }

  private static Metrics metricsOf(PrimeCore core) {
    try {
      return core.metrics();
    } catch (IllegalStateException off) {
      throw new IllegalStateException(
          "cannot bind the metrics of core '" + core.name() + "': " + off.getMessage(), off);
    }
  }

  /**
   * Registers the meters of every metered node declared now (see the class's docs) and starts
   * timing their values. Binding to a second registry registers them there too; binding again to
   * a registry this binder is bound to does nothing (its timers would count each value twice).
   *
   * <p>One binder per core and registry: the meters of a second binder would be the first one's
   * (a registry keeps one meter per name and tags), so its timers would time each value twice
   * and closing either binder would remove the other's meters. Binding a second one is refused,
   * and so is binding a core whose name, media and nodes are those of another core bound there,
   * also where the registry's meter filters rename the meters; close the first binder, or give
   * the cores distinct names.
   *
   * @param registry the registry
   * @throws IllegalStateException if {@code registry} holds the meters of a node of this core
   *     bound by another binder, or refuses one of the meters (it holds a meter of another type
   *     under that name and tags, say); the message names the node and the fix, and nothing of
   *     this binding is kept (no meter, no timing)
   */
  @Override
  public synchronized void bindTo(MeterRegistry registry) {
    Objects.requireNonNull(registry, "registry must not be null");
    for (Bound b : bound) {
      if (b.registry() == registry) {
        return;
      }
    }
    // Another binder's meters are told by what registering returns (the registry's meter for
    // that id), not looked up by name: a meter filter may have renamed them.
    Set<Meter> existing = Collections.newSetFromMap(new IdentityHashMap<>());
    existing.addAll(registry.getMeters());
    List<Bound> made = new ArrayList<>();
    List<String> names = new ArrayList<>();
    for (ServiceMetrics service : metrics.services()) {
      try {
        made.add(bindNode(registry, service, existing));
      } catch (RuntimeException e) {
        undo(registry, List.of(), made);
        throw e;
      }
      names.add(service.name());
    }
    bound.addAll(made);
    // The nodes declared now that this process does not run now (on Optimus, a service another
    // process runs, such as one this process stands by for) get their meters once it does.
    Set<String> later = new HashSet<>();
    for (TopologyNode node : core.topology().nodes()) {
      if (node.isService() && !names.contains(node.name())) {
        later.add(node.name());
      }
    }
    awaited.put(registry, later);
    snapshots.cover(names);
  }

  /**
   * Registers the meters of one node and starts timing its values.
   *
   * @throws IllegalStateException if the registry refuses a meter or holds them already (another
   *     binder's); the meters this call registered are removed
   */
  private Bound bindNode(MeterRegistry registry, ServiceMetrics service, Set<Meter> existing) {
    List<Meter> meters = new ArrayList<>();
    try {
      register(registry, service, meters);
    } catch (RuntimeException refused) {
      undo(registry, notIn(existing, meters), List.of());
      throw new IllegalStateException(
          "cannot bind the meters of node '" + service.name() + "' of core '" + metrics.core()
              + "' on " + metrics.media() + ": the registry refused one (" + refused.getMessage()
              + "); nothing of this binding is kept: remove the meter in the way from the"
              + " registry, or rename it (or the prime.service.* meters) with a meter filter,"
              + " then bind again",
          refused);
    }
    if (meters.stream().anyMatch(existing::contains)) {
      undo(registry, notIn(existing, meters), List.of());
      throw new IllegalStateException(
          "the registry already has the meters of node '" + service.name() + "' of core '"
              + metrics.core() + "' on " + metrics.media() + ", bound by another PrimeMetrics:"
              + " bind one PrimeMetrics per core and registry (close the other first), or give"
              + " cores bound to one registry distinct names");
    }
    Timer timer = (Timer) meters.get(meters.size() - 1);
    try {
      Metrics.Subscription timing =
          metrics.onProcessed(
              service.name(), (nanos, failed) -> timer.record(nanos, TimeUnit.NANOSECONDS));
      return new Bound(registry, meters, timing);
    } catch (RuntimeException e) { // the node was forgotten meanwhile (a failed declaration)
      undo(registry, meters, List.of());
      throw e;
    }
  }

  /**
   * Called after a meter read its node: once per snapshot, registers the meters of the nodes that
   * were declared when a registry was bound and that this process runs now but did not then (an
   * Optimus standby that took a service over). Not under the snapshots' monitor (see {@link
   * #bindTo}, which takes it under this one's). A node whose meters the registry refuses is left
   * without them, and said so in the log: a registry's read must not fail for it.
   */
  private void bindNewlyRun() {
    long generation = snapshots.generation();
    if (generation == checkedAt) {
      return;
    }
    synchronized (this) {
      if (generation == checkedAt) {
        return;
      }
      checkedAt = generation;
      if (awaited.values().stream().allMatch(Set::isEmpty)) {
        return;
      }
      List<String> names = metrics.names();
      List<String> adopted = new ArrayList<>();
      for (Map.Entry<MeterRegistry, Set<String>> entry : awaited.entrySet()) {
        MeterRegistry registry = entry.getKey();
        for (String name : names) {
          if (!entry.getValue().remove(name)) {
            continue;
          }
          Set<Meter> existing = Collections.newSetFromMap(new IdentityHashMap<>());
          existing.addAll(registry.getMeters());
          try {
            bound.add(bindNode(registry, metrics.service(name), existing));
            adopted.add(name);
          } catch (RuntimeException e) {
            System.getLogger(PrimeMetrics.class.getName())
                .log(System.Logger.Level.WARNING,
                    "node '" + name + "' of core '" + metrics.core() + "' runs here now but gets"
                        + " no meters: " + e.getMessage());
          }
        }
      }
      snapshots.cover(adopted);
    }
  }

  /** {@return those of {@code meters} that {@code existing} does not hold} */
  private static List<Meter> notIn(Set<Meter> existing, List<Meter> meters) {
    return meters.stream().filter(meter -> !existing.contains(meter)).toList();
  }

  /**
   * Undoes a binding that cannot finish: removes {@code meters}, the meters it registered for the
   * node at hand, and those of the nodes bound before, and stops their timing.
   */
  private static void undo(MeterRegistry registry, List<Meter> meters, List<Bound> made) {
    meters.forEach(registry::remove);
    for (Bound b : made) {
      b.timing().close();
      b.meters().forEach(registry::remove);
    }
  }

  /**
   * Registers the meters of one node, its timer last, adding each to {@code meters} as soon as it
   * is registered (so that a registry refusing one leaves the list of those to remove).
   */
  private void register(MeterRegistry registry, ServiceMetrics service, List<Meter> meters) {
    String name = service.name();
    Tags tags = tagsOf(service);
    meters.add(counter(registry, VALUES_IN, "values given to the node", tags, name,
        ServiceMetrics::valuesIn));
    meters.add(counter(registry, VALUES_OUT, "values the node gave out", tags, name,
        ServiceMetrics::valuesOut));
    meters.add(counter(registry, FAILURES, "values on which the node's logic threw", tags,
        name, ServiceMetrics::failures));
    meters.add(counter(registry, MISSED, "values the node's input missed", tags, name,
        ServiceMetrics::missed));
    meters.add(gauge(registry, DEAD_LETTERS, "values the media set aside as dead letters",
        tags, name, ServiceMetrics::deadLetters));
    if (metrics.hasQueue(name)) {
      meters.add(gauge(registry, QUEUE_DEPTH, "values in the node's input not finished",
          tags, name, ServiceMetrics::queueDepth));
    }
    meters.add(
        Timer.builder(PROCESSING)
            .description("the time the node took per value")
            .tags(tags)
            .publishPercentileHistogram()
            .register(registry));
  }

  private Tags tagsOf(ServiceMetrics service) {
    return Tags.of(
        "service", service.name(),
        "kind", service.kind(),
        "media", metrics.media(),
        "core", metrics.core());
  }

  // A registry keeps a meter's object only weakly (a counter whose object is gone stops at its
  // last count, a gauge gives NaN), and its function strongly: the functions read this binder's
  // snapshots, so that its meters go on reading the core while they are registered, also when
  // the program keeps no reference to the binder (PrimeMetrics.of(core).bindTo(registry)).
  private FunctionCounter counter(
      MeterRegistry registry,
      String meter,
      String description,
      Tags tags,
      String service,
      ToDoubleFunction<ServiceMetrics> count) {
    return FunctionCounter.builder(
            meter,
            snapshots,
            unused -> {
              ServiceMetrics now = snapshots.service(service);
              bindNewlyRun();
              return now == null ? Double.NaN : count.applyAsDouble(now);
            })
        .description(description)
        .baseUnit("values")
        .tags(tags)
        .register(registry);
  }

  private Gauge gauge(
      MeterRegistry registry,
      String meter,
      String description,
      Tags tags,
      String service,
      ToDoubleFunction<ServiceMetrics> value) {
    return Gauge.builder(
            meter,
            snapshots,
            unused -> {
              ServiceMetrics now = snapshots.service(service);
              bindNewlyRun();
              double v = now == null ? -1 : value.applyAsDouble(now);
              return v < 0 ? Double.NaN : v; // no longer metered here, or unknown now
            })
        .description(description)
        .baseUnit("values")
        .tags(tags)
        .register(registry);
  }

  /** Removes every meter this binder registered and stops timing; closing twice does nothing. */
  @Override
  public synchronized void close() {
    for (Bound b : bound) {
      b.timing().close();
      b.meters().forEach(b.registry()::remove);
    }
    bound.clear();
    awaited.clear();
  }

  /** The meters of one node in one registry, and the listener that feeds its timer. */
  private record Bound(MeterRegistry registry, List<Meter> meters, Metrics.Subscription timing) {}

  @Override
  public String toString() {
    return "PrimeMetrics[" + core.name() + "]";
  }
}

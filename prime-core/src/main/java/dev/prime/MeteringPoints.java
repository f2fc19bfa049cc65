package dev.prime;

import dev.prime.topology.TopologyNode;
import java.time.Duration;
import java.util.Iterator;
import java.util.Map;
import java.util.concurrent.ConcurrentHashMap;
import java.util.function.BooleanSupplier;
import java.util.function.Consumer;
import java.util.function.Predicate;

/**
 * Where a core meters (see {@link Metrics}): the model compiler asks it for a tap at each metered
 * node as the node is compiled, the way it asks {@link RecordingPoints} for recording taps. A
 * core whose metrics are off has no {@code MeteringPoints}, so nothing is compiled in and nothing
 * runs per value.
 *
 * <p>A chain's tap wraps the block the media is given for it, so it runs wherever the media runs
 * that block (the caller's thread, a fused Radiant class, the Optimus process hosting the
 * service); a filter's, flat-map's or listener's wraps its function, whichever media runs the
 * service; an event source's are two subscribers of its event block around the media's.
 */
final class MeteringPoints {
  private final PrimeCore core;
  private final InProcessServices unsubscriber; // closes its event block subscriptions at close
  private final Metrics metrics;
  private final Map<String, SourcePoint> eventSources = new ConcurrentHashMap<>();

  MeteringPoints(PrimeCore core, String media, ServiceGauges gauges, InProcessServices memory) {
    this.core = core;
    this.unsubscriber = memory;
    this.metrics =
        new Metrics(core.name(), media, core.topologyRecorder(), gauges, core::isHostedHere);
  }

  Metrics metrics() {
    return metrics;
  }

  private ServiceMeter meter(TopologyNode node) {
    ServiceMeter meter =
        new ServiceMeter(node.name(), node.getClass().getSimpleName(), metrics.listenerFailures());
    metrics.add(meter);
    return meter;
  }

  /** The block of a metered chain node. */
  <I, O> Block<I, O> chain(TopologyNode node, Block<I, O> block) {
    return new ChainTap<>(meter(node), block);
  }

  /**
   * The logic of a filter, flat-map or listener with its tap; the meter, for the queue depth of
   * an in-memory input.
   */
  @SuppressWarnings("unchecked")
  Metered service(TopologyNode node, NodeLogic logic) {
    ServiceMeter meter = meter(node);
    NodeLogic tapped;
    if (logic instanceof NodeLogic.Condition condition) {
      tapped = new NodeLogic.Condition(new FilterTap(meter, (Predicate<Object>) condition.condition()));
    } else if (logic instanceof NodeLogic.Expand expand) {
      tapped = new NodeLogic.Expand(new FlatMapTap(meter, (Block<Object, ? extends Iterable<?>>) expand.block()));
    } else if (logic instanceof NodeLogic.Listen listen) {
      tapped = new NodeLogic.Listen(new ListenerTap(meter, (Consumer<Object>) listen.listener()));
    } else {
      throw new IllegalStateException("not a metered service of a source: " + node);
    }
    return new Metered(meter, tapped);
  }

  /** A service's logic with its tap, and its meter. */
  record Metered(ServiceMeter meter, NodeLogic logic) {}

  /** Starts metering an event source; see {@link RecordingPoints#beforeSource}. */
  SourcePoint beforeSource(TopologyNode node, EventBlock<?> events) {
    boolean combinator = node instanceof TopologyNode.Combinator;
    SourcePoint point = new SourcePoint(meter(node), events, combinator);
    if (!combinator) {
      eventSources.put(node.name(), point);
    }
    return point;
  }

  /**
   * Counts {@code count} values that the media published to the event source {@code name}
   * together, not through its event block ({@link PrimeCore#publishedTogether}), as its event
   * block's publishes are counted: each in; and, if the media accepted them, each out, timed with
   * the whole publish's time. Nothing for a name that is not a metered event source.
   */
  void countAll(String name, int count, long nanos, boolean accepted) {
    SourcePoint point = eventSources.get(name);
    if (point != null) {
      point.countAll(count, nanos, accepted);
    }
  }

  /**
   * The step of a combinator's inputs with its tap: in = values taken from the inputs, timed,
   * failures = values whose step threw; out is what its output source accepted (counted by its
   * {@link SourcePoint}, so the combinator's output source must be compiled first).
   */
  CombinedInputs.InputStep combinator(String name, CombinedInputs.InputStep step) {
    ServiceMeter meter = metrics.registered(name);
    if (meter == null) {
      throw new IllegalStateException("combinator '" + name + "' has no output source yet");
    }
    return (input, value) -> {
      meter.in();
      long start = System.nanoTime();
      try {
        step.accept(input, value);
      } catch (Throwable failed) { // a checked exception thrown sneakily fails the value too
        meter.processed(System.nanoTime() - start, true);
        throw failed;
      }
      meter.processed(System.nanoTime() - start, false);
    };
  }

  /**
   * A generic service with its tap: each {@link GenericService#work()} is one value in and, if it
   * returns, one out; if it throws, a failure, unless {@code stopping} holds (the step ended
   * because the service stops: timed, neither out nor failed, as the loop does not report it).
   */
  GenericService genericService(TopologyNode node, GenericService service, BooleanSupplier stopping) {
    return new GenericServiceTap(meter(node), service, stopping);
  }

  private record GenericServiceTap(
      ServiceMeter meter, GenericService service, BooleanSupplier stopping)
      implements GenericService {
    @Override
    public void initialize() throws Exception {
      service.initialize();
    }

    @Override
    public void work() throws Exception {
      meter.in();
      long start = System.nanoTime();
      try {
        service.work();
      } catch (Exception | Error failed) {
        meter.processed(System.nanoTime() - start, !stopping.getAsBoolean());
        throw failed;
      }
      meter.processed(System.nanoTime() - start, false);
      meter.out();
    }

    @Override
    public void shutdown() throws Exception {
      service.shutdown();
    }

    @Override
    public Duration backoff(int failures) {
      return service.backoff(failures);
    }
  }

  /** The metering of one event source: publishes in, accepted by the media out, and the time. */
  final class SourcePoint {
    private final ServiceMeter meter;
    private final EventBlock<?> events;
    private final ThreadLocal<long[]> started = ThreadLocal.withInitial(() -> new long[1]);
    private final EventBlock.Subscription counting;

    private final boolean outputOnly; // a combinator's: its inputs are counted by its input tap

    private SourcePoint(ServiceMeter meter, EventBlock<?> events, boolean outputOnly) {
      this.meter = meter;
      this.events = events;
      this.outputOnly = outputOnly;
      this.counting =
          outputOnly
              ? () -> {}
              : events.subscribe(
                  value -> {
                    meter.in();
                    started.get()[0] = System.nanoTime();
                  });
    }

    /**
     * Subscribes the subscriber that counts what the media accepted, after the media's; an
     * in-memory source's readers' misses are counted by the source. Both subscribers leave the
     * event block when the core closes.
     */
    void afterMedia(Source<?> source) {
      if (source instanceof MemorySource<?> memory) {
        meter.missed(memory::missedByReaders);
      }
      unsubscriber.unsubscribeOnClose(counting);
      EventBlock.Subscription accepted =
          events.subscribe(
              value -> {
                if (core.isClosed()) {
                  return;
                }
                meter.out();
                if (!outputOnly) {
                  meter.processed(System.nanoTime() - started.get()[0], false);
                }
              });
      unsubscriber.unsubscribeOnClose(accepted);
    }

    /** Stops counting: the media made no source. */
    void cancel() {
      counting.close();
      eventSources.values().remove(this);
    }

    private void countAll(int count, long nanos, boolean accepted) {
      for (int i = 0; i < count; i++) {
        meter.in();
      }
      if (!accepted || core.isClosed()) {
        return;
      }
      for (int i = 0; i < count; i++) {
        meter.out();
        meter.processed(nanos, false);
      }
    }
  }

  /** Runs a value through a node's logic, counting and timing it. */
  private record ChainTap<I, O>(ServiceMeter meter, Block<I, O> block) implements Block<I, O> {
    @Override
    public O process(I input) {
      meter.in();
      long start = System.nanoTime();
      O output;
      try {
        output = block.process(input);
      } catch (Throwable failed) { // a checked exception thrown sneakily fails the value too
        meter.processed(System.nanoTime() - start, true);
        throw failed;
      }
      meter.processed(System.nanoTime() - start, false);
      if (output != null) {
        meter.out();
      }
      return output;
    }
  }

  private record FilterTap(ServiceMeter meter, Predicate<Object> predicate)
      implements Predicate<Object> {
    @Override
    public boolean test(Object value) {
      meter.in();
      long start = System.nanoTime();
      boolean passed;
      try {
        passed = predicate.test(value);
      } catch (Throwable failed) { // a checked exception thrown sneakily fails the value too
        meter.processed(System.nanoTime() - start, true);
        throw failed;
      }
      meter.processed(System.nanoTime() - start, false);
      if (passed) {
        meter.out();
      }
      return passed;
    }
  }

  private record FlatMapTap(ServiceMeter meter, Block<Object, ? extends Iterable<?>> block)
      implements Block<Object, Iterable<?>> {
    @Override
    public Iterable<?> process(Object input) {
      meter.in();
      long start = System.nanoTime();
      Iterable<?> outputs;
      try {
        outputs = block.process(input);
      } catch (Throwable failed) { // a checked exception thrown sneakily fails the value too
        meter.processed(System.nanoTime() - start, true);
        throw failed;
      }
      meter.processed(System.nanoTime() - start, false);
      return outputs == null ? null : new CountedOutputs<>(meter, outputs);
    }
  }

  /** A flat-map's outputs, counting the non-null ones as the service takes them. */
  private record CountedOutputs<R>(ServiceMeter meter, Iterable<R> outputs) implements Iterable<R> {
    @Override
    public Iterator<R> iterator() {
      Iterator<R> values = outputs.iterator();
      return new Iterator<>() {
        @Override
        public boolean hasNext() {
          return values.hasNext();
        }

        @Override
        public R next() {
          R value = values.next();
          if (value != null) {
            meter.out();
          }
          return value;
        }
      };
    }
  }

  private record ListenerTap(ServiceMeter meter, Consumer<Object> listener)
      implements Consumer<Object> {
    @Override
    public void accept(Object value) {
      meter.in();
      long start = System.nanoTime();
      try {
        listener.accept(value);
      } catch (Throwable failed) { // a checked exception thrown sneakily fails the value too
        meter.processed(System.nanoTime() - start, true);
        throw failed;
      }
      meter.processed(System.nanoTime() - start, false);
    }
  }
}

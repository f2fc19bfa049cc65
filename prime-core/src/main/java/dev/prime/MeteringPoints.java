package dev.prime;

import dev.prime.spi.NodeLogic;
import dev.prime.spi.ServiceGauges;
import dev.prime.topology.TopologyNode;
import java.util.Iterator;
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
  private final Metrics metrics;

  MeteringPoints(PrimeCore core, String media, ServiceGauges gauges) {
    this.core = core;
    this.metrics =
        new Metrics(core.name(), media, core.topologyRecorder(), gauges, core::isHostedHere);
  }

  Metrics metrics() {
    return metrics;
  }

  private ServiceMeter meter(TopologyNode node) {
    ServiceMeter meter = new ServiceMeter(node.name(), node.getClass().getSimpleName());
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
    return new SourcePoint(meter(node), events);
  }

  /** The metering of one event source: publishes in, accepted by the media out, and the time. */
  final class SourcePoint {
    private final ServiceMeter meter;
    private final EventBlock<?> events;
    private final ThreadLocal<long[]> started = ThreadLocal.withInitial(() -> new long[1]);
    private final EventBlock.Subscription counting;

    private SourcePoint(ServiceMeter meter, EventBlock<?> events) {
      this.meter = meter;
      this.events = events;
      this.counting =
          events.subscribe(
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
      core.inProcessServices().unsubscribeOnClose(counting);
      EventBlock.Subscription accepted =
          events.subscribe(
              value -> {
                if (core.isClosed()) {
                  return;
                }
                meter.out();
                meter.processed(System.nanoTime() - started.get()[0], false);
              });
      core.inProcessServices().unsubscribeOnClose(accepted);
    }

    /** Stops counting: the media made no source. */
    void cancel() {
      counting.close();
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
      } catch (RuntimeException | Error failed) {
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
      } catch (RuntimeException | Error failed) {
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
      } catch (RuntimeException | Error failed) {
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
      } catch (RuntimeException | Error failed) {
        meter.processed(System.nanoTime() - start, true);
        throw failed;
      }
      meter.processed(System.nanoTime() - start, false);
    }
  }
}

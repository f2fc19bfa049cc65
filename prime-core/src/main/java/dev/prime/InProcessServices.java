package dev.prime;

import dev.prime.internal.ServiceThreads;
import dev.prime.topology.TopologyNode;
import java.util.ArrayList;
import java.util.List;
import java.util.function.BooleanSupplier;
import java.util.function.Consumer;
import java.util.function.Predicate;
import java.util.function.Supplier;

/**
 * The core's in-memory {@link SourceCompiler}, which a media that runs in one process uses as it
 * is: in-memory broadcast sources fed by event blocks, and services (a chain on a source, a
 * filter, a flat-map, a listener) that each run on a thread of the core. A media with a source
 * compiler of its own (Optimus) still gets this one for the services of sources that are not its
 * own (another core's): they read any source through its readers, so their "form" of a source is
 * the source itself, and of a source link's chain a supplier of the chain's block, taken once the
 * service's input is open (making a block may have effects, such as binding Optimus services).
 *
 * <p>Design note. The sources and the event-block subscriptions are kept in lists guarded by the
 * sources list, so that {@link #close()} unsubscribes and closes every one exactly once, and a
 * source made after the core closed is refused ({@link PrimeCore#ensureOpen()} under the same
 * lock). Service threads belong to {@link ServiceThreads}, which starts, names and stops them.
 */
final class InProcessServices implements SourceCompiler<Source<?>> {
  private final PrimeCore core;
  private final ServiceThreads threads;
  private final BooleanSupplier closed; // core::isClosed, made once: asked on a service's hot path
  private final List<MemorySource<?>> sources = new ArrayList<>(); // guarded by itself
  private final List<EventBlock.Subscription> subscriptions = new ArrayList<>(); // guarded by sources
  private volatile MeteringPoints metering; // null: metrics are off

  InProcessServices(PrimeCore core, ServiceThreads threads) {
    this.core = core;
    this.closed = core::isClosed;
    this.threads = threads;
  }

  @Override
  @SuppressWarnings({"unchecked", "rawtypes"})
  public Class<Source<?>> form() {
    return (Class) Source.class;
  }

  /** Meters the filters, flat-maps and listeners made from now on ({@code null}: none). */
  void meterWith(MeteringPoints points) {
    this.metering = points;
  }

  /**
   * The function of the filter, flat-map or listener {@code name} reading {@code input}: with its
   * metering tap (and its meter told the input's depth) if metrics are on.
   */
  private NodeLogic metered(String name, NodeLogic logic, Source<?> source, Reader<?> input) {
    MeteringPoints points = metering;
    if (points == null) {
      return logic;
    }
    MeteringPoints.Metered metered = points.service(core.topologyRecorder().node(name), logic);
    if (source instanceof MemorySource<?> memory) {
      metered.meter().queue(() -> memory.backlog(input));
    }
    return metered.logic();
  }

  /** An in-memory source publishing what {@code events} publishes. */
  @Override
  public <T> Source<T> eventSource(String name, EventBlock<T> events) {
    MemorySource<T> source = newSource(name);
    synchronized (sources) {
      subscriptions.add(
          events.subscribe(
              value -> {
                try {
                  source.publish(value);
                } catch (CoreClosedException closing) {
                  // the core closed while this value was on its way: nobody can read it any more
                }
              }));
    }
    return source;
  }

  /**
   * Compiles a service of any source: a {@link TopologyNode.SourceLink} running {@code chain} (a
   * {@code Supplier} of the chain's block, which the model compiler claims once this returned), a {@link
   * TopologyNode.Filter}, a {@link TopologyNode.FlatMap} or a {@link TopologyNode.Listener}.
   */
  @Override
  @SuppressWarnings({"unchecked", "rawtypes"})
  public Source<?> service(TopologyNode node, NodeLogic logic, Source<?> input, Object chain) {
    String name = node.name();
    Source in = input;
    if (node instanceof TopologyNode.SourceLink link) {
      return link(name, takerOf(link), in, (Supplier) chain);
    }
    if (node instanceof TopologyNode.Filter) {
      return filter(name, in, ((NodeLogic.Condition) logic).condition());
    }
    if (node instanceof TopologyNode.FlatMap) {
      return flatMap(name, in, ((NodeLogic.Expand) logic).block());
    }
    if (node instanceof TopologyNode.Listener) {
      listen(name, in, ((NodeLogic.Listen) logic).listener());
      return null;
    }
    throw new IllegalStateException("not a service of a source: " + node);
  }

  /**
   * The service that takes the values of a source link, as the user named it and as {@link
   * PrimeCore#serviceNames()} lists it: the linked chain, or the first of chains linked before
   * (on Optimus the service whose input that is), so that a {@link QueueFullException} names the
   * same service on every media.
   */
  private String takerOf(TopologyNode.SourceLink link) {
    String chain = link.chain();
    try {
      TopologyNode node = core.topologyRecorder().node(chain);
      while (node instanceof TopologyNode.Link linked) {
        chain = linked.first();
        node = core.topologyRecorder().node(chain);
      }
    } catch (IllegalArgumentException notRecorded) {
      // not a chain of this core's diagram: its own name
    }
    return chain;
  }

  /**
   * A service running the chain's block on every value of {@code input}; its non-null outputs.
   * The block is made only once the service's input is open, so a link whose input fails has
   * done nothing to the chain.
   *
   * @param taker the service as {@link PrimeCore#serviceNames()} lists it: the name a {@link
   *     QueueFullException} of its full input, the error handler (for a failure not of a chain)
   *     and the ERROR line of a {@link VirtualMachineError} that ends it give
   */
  private <I, O> Source<O> link(
      String name, String taker, Source<I> input, Supplier<Block<I, O>> chain) {
    Reader<I> values = serviceInput(taker, input);
    MemorySource<O> out;
    Block<I, O> block;
    try {
      block = chain.get();
      out = newSource(name);
    } catch (RuntimeException | Error e) {
      values.close();
      throw e;
    }
    threads.add(
        name,
        taker,
        new SourceService<I>(
            taker,
            values,
            value -> {
              O output = block.process(value);
              if (output != null) {
                clearOwnInterrupt();
                out.publish(output);
              }
            },
            core.config().errorHandler(),
            core::isClosed),
        values::close); // a core closed unstarted holds no publisher of another core up
    return out;
  }

  /** A service republishing the values of {@code input} that pass. */
  @SuppressWarnings("unchecked")
  private <T> Source<T> filter(String name, Source<T> input, Predicate<? super T> predicate) {
    MemorySource<T> out = newSource(name);
    Reader<T> values = serviceInput(name, input);
    Predicate<? super T> test =
        (Predicate<? super T>)
            ((NodeLogic.Condition) metered(name, new NodeLogic.Condition(predicate), input, values))
                .condition();
    run(
        name,
        values,
        value -> {
          if (test.test(value)) {
            clearOwnInterrupt();
            out.publish(value);
          }
        });
    return out;
  }

  /** A service publishing every non-null value {@code block} makes of each value of {@code input}. */
  @SuppressWarnings("unchecked")
  private <T, R> Source<R> flatMap(
      String name, Source<T> input, Block<? super T, ? extends Iterable<? extends R>> block) {
    MemorySource<R> out = newSource(name);
    Reader<T> values = serviceInput(name, input);
    Block<? super T, ? extends Iterable<? extends R>> expand =
        (Block<? super T, ? extends Iterable<? extends R>>)
            ((NodeLogic.Expand) metered(name, new NodeLogic.Expand(block), input, values)).block();
    run(
        name,
        values,
        value -> {
          Iterable<? extends R> outputs = expand.process(value);
          if (outputs != null) {
            for (R output : outputs) {
              if (output != null) {
                clearOwnInterrupt();
                out.publish(output);
              }
            }
          }
        });
    return out;
  }

  /** A service calling {@code listener} with every value of {@code input}. */
  @SuppressWarnings("unchecked")
  private <T> void listen(String name, Source<T> input, Consumer<? super T> listener) {
    Reader<T> values = serviceInput(name, input);
    run(
        name,
        values,
        (Consumer<? super T>)
            ((NodeLogic.Listen) metered(name, new NodeLogic.Listen(listener), input, values))
                .listener());
  }

  /**
   * Clears the interrupt flag that the user's code of a service set on the service's own thread
   * while the core is open (a block that restored the flag of an {@code InterruptedException} it
   * caught), before the service publishes what that code made: a publish that waits for room in
   * a full input would take the flag for a stop and fail. A close marks the core closed before it
   * interrupts, so the flag of a close stays.
   */
  private void clearOwnInterrupt() {
    ServiceThreads.clearOwnInterrupt(closed);
  }

  /** A generic service on a thread of the core; it stops when the core closes. */
  void generic(String name, GenericService service) {
    threads.add(
        name,
        new GenericServiceLoop(name, service, core.config().errorHandler(), core::isClosed));
  }

  /** A service on a thread of the core: each value of {@code reader} goes to {@code step}. */
  <T> void run(String name, Reader<T> reader, Consumer<? super T> step) {
    threads.add(
        name,
        name,
        new SourceService<>(name, reader, step, core.config().errorHandler(), core::isClosed),
        reader::close); // a core closed unstarted holds no publisher of another core up
  }

  /**
   * Closes {@code subscription} when the core closes (at once if it is closing): for the
   * recording's and metering's subscribers to the program's event blocks, which outlive no core.
   */
  void unsubscribeOnClose(EventBlock.Subscription subscription) {
    synchronized (sources) {
      if (!core.isClosed()) { // close() marks the core closed before it takes this lock
        subscriptions.add(subscription);
        return;
      }
    }
    subscription.close();
  }

  /**
   * Closes {@code reader}, which this core opened on another core's source (a collector's), when
   * this core closes (at once if it is closing): that source stays open, and a wait in the reader
   * must end with this core.
   */
  void closeOnClose(Reader<?> reader) {
    unsubscribeOnClose(reader::close);
  }

  /** Unsubscribes from every event block and closes every source, waking their readers. */
  void close() {
    List<MemorySource<?>> closing;
    synchronized (sources) {
      subscriptions.forEach(EventBlock.Subscription::close);
      subscriptions.clear();
      closing = new ArrayList<>(sources);
      sources.clear();
    }
    closing.forEach(MemorySource::close);
  }

  /** A reader for one of the core's services: not one of the program's, so not recorded. */
  static <T> Reader<T> serviceReader(Source<T> source) {
    return source instanceof MediaSource<T> media ? media.serviceReader() : source.reader();
  }

  /**
   * The input of service {@code name}: on an in-memory source a queue that holds publishers up
   * rather than let the service miss a value ({@link MemorySource#serviceInput}); on another
   * media's source, its service reader.
   */
  private static <T> Reader<T> serviceInput(String name, Source<T> source) {
    return source instanceof MemorySource<T> memory
        ? memory.serviceInput(name)
        : serviceReader(source);
  }

  private <T> MemorySource<T> newSource(String name) {
    CoreConfig config = core.config();
    MemorySource<T> source =
        new MemorySource<>(
            core,
            name,
            config.sourceRetention(),
            config.valueCopies(),
            () -> core.topologyRecorder().reader(name));
    synchronized (sources) {
      core.ensureOpen();
      sources.add(source);
    }
    return source;
  }
}

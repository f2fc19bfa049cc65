package dev.prime.bench;

import com.lmax.disruptor.EventHandler;
import com.lmax.disruptor.RingBuffer;
import com.lmax.disruptor.YieldingWaitStrategy;
import com.lmax.disruptor.dsl.Disruptor;
import com.lmax.disruptor.dsl.ProducerType;
import com.lmax.disruptor.util.DaemonThreadFactory;
import dev.prime.Block;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.Reader;
import dev.prime.bench.PacketBlocks.Add;
import dev.prime.liberty.LibertyCore;
import java.util.concurrent.TimeUnit;
import org.openjdk.jmh.annotations.Benchmark;
import org.openjdk.jmh.annotations.BenchmarkMode;
import org.openjdk.jmh.annotations.Fork;
import org.openjdk.jmh.annotations.Level;
import org.openjdk.jmh.annotations.Measurement;
import org.openjdk.jmh.annotations.Mode;
import org.openjdk.jmh.annotations.OperationsPerInvocation;
import org.openjdk.jmh.annotations.OutputTimeUnit;
import org.openjdk.jmh.annotations.Scope;
import org.openjdk.jmh.annotations.Setup;
import org.openjdk.jmh.annotations.State;
import org.openjdk.jmh.annotations.TearDown;
import org.openjdk.jmh.annotations.Threads;
import org.openjdk.jmh.annotations.Warmup;
import reactor.core.Disposable;
import reactor.core.publisher.Flux;
import reactor.core.publisher.Sinks;
import reactor.core.scheduler.Scheduler;
import reactor.core.scheduler.Schedulers;

/**
 * The asynchronous mode through a thread hand-off: the benchmark thread publishes a batch of
 * {@link #BATCH} packets as fast as the pipeline takes them, a consumer thread runs the 4 adders
 * on each, and the benchmark thread waits for the whole batch's outputs; the time is per packet.
 * Producer and consumer overlap, so this is throughput with data flowing constantly.
 *
 * <p>One pipeline is two threads (producer and consumer), so on the 2-core machine of
 * BENCHMARKS.md it loads both cores. Pipelines: a Prime source with a Liberty chain linked to it,
 * a Kotlin Channel, Reactor with {@code publishOn}, and the LMAX Disruptor, the floor of a thread
 * hand-off on the JVM. Each does one thread hand-off: the consumer thread reports each output to
 * {@link Arrivals} (for Prime, the chain's last block does, on the source's service thread) and
 * the benchmark thread waits on that count. {@link #primeSourceAndReader} is the earlier Prime row,
 * which read the outputs back with a {@link Reader}: two hand-offs, kept for comparison. Run it
 * with {@code -p scenario=monomorphic}: the table's runner does.
 */
@BenchmarkMode(Mode.AverageTime)
@OutputTimeUnit(TimeUnit.NANOSECONDS)
@Warmup(iterations = 5, time = 1)
@Measurement(iterations = 5, time = 1)
@Fork(2)
@Threads(1)
@OperationsPerInvocation(AsyncHandOffBenchmark.BATCH)
public class AsyncHandOffBenchmark {
  /** Packets per benchmark call; every pipeline holds at least this many in flight. */
  public static final int BATCH = 256;

  /** The batch's packets, distinct so none is in two places of the pipeline at once. */
  @State(Scope.Thread)
  public static class Batch {
    /** The packets. */
    public Packet[] packets;

    /**
     * @param shape the parameters
     */
    @Setup(Level.Trial)
    public void build(Shape shape) {
      packets = new Packet[BATCH];
      for (int i = 0; i < BATCH; i++) {
        packets[i] = Packet.ofSize(shape.payload);
      }
    }
  }

  /**
   * The last block of the Prime row's chain: reports each output to {@link Arrivals}, on the
   * thread that runs the chain (the source's service thread), as the peers' consumers do, and
   * passes the packet on (the linked chain's output source gets it, as any linked chain's does).
   */
  public static final class CountArrival implements Block<Packet, Packet> {
    private final Arrivals arrivals;

    /**
     * @param arrivals where each output is reported
     */
    public CountArrival(Arrivals arrivals) {
      this.arrivals = arrivals;
    }

    @Override
    public Packet process(Packet packet) {
      arrivals.arrive(packet.value);
      return packet;
    }
  }

  /**
   * A Prime source with a Liberty chain linked to it: the 4 adders and then {@link CountArrival},
   * all on the source's service thread: one hand-off, like the peers.
   */
  @State(Scope.Thread)
  public static class PrimeSource {
    /** Where the benchmark publishes. */
    public EventBlock<Packet> events;

    /** Counts the outputs: the chain's last block reports each. */
    public final Arrivals arrivals = new Arrivals();

    /** Outputs expected so far. */
    public long expected;

    private LibertyCore core;

    /**
     * @param shape the parameters
     */
    @Setup(Level.Trial)
    public void build(Shape shape) {
      core = new LibertyCore(CoreConfig.builder().sourceRetention(4 * BATCH).build());
      events = new EventBlock<>();
      core.source(events)
          .then(ChainShapes.adderChain(core, shape.length).then(new CountArrival(arrivals)));
      core.start();
    }

    /** Closes the core and its service thread. */
    @TearDown(Level.Trial)
    public void close() {
      core.close();
    }
  }

  /**
   * The earlier Prime row: a Prime source, the Liberty chain linked to it, and a reader of the
   * chain's outputs on the benchmark thread: two hand-offs (to the service thread and back).
   */
  @State(Scope.Thread)
  public static class PrimeSourceAndReader {
    /** Where the benchmark publishes. */
    public EventBlock<Packet> events;

    /** Reads the linked chain's outputs. */
    public Reader<Packet> outputs;

    private LibertyCore core;

    /**
     * @param shape the parameters
     */
    @Setup(Level.Trial)
    public void build(Shape shape) {
      core = new LibertyCore(CoreConfig.builder().sourceRetention(4 * BATCH).build());
      events = new EventBlock<>();
      outputs =
          core.source(events).then(ChainShapes.adderChain(core, shape.length)).reader();
      core.start();
    }

    /** Closes the core and its service thread. */
    @TearDown(Level.Trial)
    public void close() {
      core.close();
    }
  }

  /** A Kotlin Channel with one consumer coroutine. */
  @State(Scope.Thread)
  public static class KotlinChannel {
    /** The pipeline. */
    public ChannelPipeline pipeline;

    /** Outputs expected so far. */
    public long expected;

    /**
     * @param shape the parameters
     */
    @Setup(Level.Trial)
    public void build(Shape shape) {
      pipeline = new ChannelPipeline(ChainShapes.directAdders(shape.length), 4 * BATCH);
    }

    /** Closes the channel and its thread. */
    @TearDown(Level.Trial)
    public void close() {
      pipeline.close();
    }
  }

  /** Reactor: a unicast sink, {@code publishOn} a single-thread scheduler, the adders. */
  @State(Scope.Thread)
  public static class ReactorPublishOn {
    /** Where the benchmark emits. */
    public Sinks.Many<Packet> sink;

    /** Counts the outputs. */
    public final Arrivals arrivals = new Arrivals();

    /** Outputs expected so far. */
    public long expected;

    private Scheduler scheduler;
    private Disposable subscription;

    /**
     * @param shape the parameters
     */
    @Setup(Level.Trial)
    public void build(Shape shape) {
      scheduler = Schedulers.newSingle("bench-reactor", true);
      sink = Sinks.many().unicast().onBackpressureBuffer();
      Flux<Packet> pipeline = sink.asFlux().publishOn(scheduler, BATCH);
      for (Add adder : ChainShapes.directAdders(shape.length)) {
        pipeline = pipeline.map(adder::process);
      }
      subscription = pipeline.subscribe(packet -> arrivals.arrive(packet.value));
    }

    /** Ends the subscription and the scheduler's thread. */
    @TearDown(Level.Trial)
    public void close() {
      sink.tryEmitComplete();
      subscription.dispose();
      scheduler.dispose();
    }
  }

  /** One slot of the Disruptor's ring. */
  public static final class Slot {
    /** The packet in the slot. */
    public Packet packet;

    /** An empty slot. */
    public Slot() {}
  }

  /** The Disruptor: a ring of {@link Slot}s, one handler thread that runs the adders. */
  @State(Scope.Thread)
  public static class LmaxDisruptor {
    /** Where the benchmark publishes. */
    public RingBuffer<Slot> ring;

    /** Counts the outputs. */
    public final Arrivals arrivals = new Arrivals();

    /** Outputs expected so far. */
    public long expected;

    private Disruptor<Slot> disruptor;

    /**
     * @param shape the parameters
     */
    @Setup(Level.Trial)
    public void build(Shape shape) {
      Add[] adders = ChainShapes.directAdders(shape.length);
      disruptor =
          new Disruptor<>(
              Slot::new,
              4 * BATCH,
              DaemonThreadFactory.INSTANCE,
              ProducerType.SINGLE,
              new YieldingWaitStrategy());
      EventHandler<Slot> handler =
          (slot, sequence, endOfBatch) ->
              arrivals.arrive(ChainShapes.runDirect(adders, slot.packet).value);
      disruptor.handleEventsWith(handler);
      ring = disruptor.start();
    }

    /** Stops the handler thread. */
    @TearDown(Level.Trial)
    public void close() {
      disruptor.halt();
    }
  }

  /**
   * Prime source: publish the batch, wait for its outputs, which the linked chain's last block
   * counts on the service thread. One thread hand-off, as the peers.
   *
   * @param batch the packets
   * @param source the pipeline
   * @return the sum of the outputs' values
   */
  @Benchmark
  public long primeSource(Batch batch, PrimeSource source) {
    for (Packet packet : batch.packets) {
      source.events.publish(packet);
    }
    source.expected += BATCH;
    return source.arrivals.await(source.expected);
  }

  /**
   * The earlier Prime row, for continuity: publish the batch, then read its outputs back with a
   * {@link Reader} on the benchmark thread, one {@code take()} per value. Two thread hand-offs
   * (benchmark thread to service thread, service thread to benchmark thread through the chain's
   * output source), so its time is a round trip, not comparable with the peers' one hand-off.
   *
   * @param batch the packets
   * @param source the pipeline
   * @return the sum of the outputs' values
   * @throws InterruptedException if interrupted while waiting for an output
   */
  @Benchmark
  public long primeSourceAndReader(Batch batch, PrimeSourceAndReader source)
      throws InterruptedException {
    for (Packet packet : batch.packets) {
      source.events.publish(packet);
    }
    long sum = 0;
    for (int i = 0; i < BATCH; i++) {
      sum += source.outputs.take().value;
    }
    return sum;
  }

  /**
   * Kotlin Channel: send the batch, wait for its outputs.
   *
   * @param batch the packets
   * @param channel the pipeline
   * @return the sum of the outputs' values
   */
  @Benchmark
  public long kotlinChannel(Batch batch, KotlinChannel channel) {
    for (Packet packet : batch.packets) {
      channel.pipeline.send(packet);
    }
    channel.expected += BATCH;
    return channel.pipeline.getArrivals().await(channel.expected);
  }

  /**
   * Reactor with {@code publishOn}: emit the batch, wait for its outputs.
   *
   * @param batch the packets
   * @param reactor the pipeline
   * @return the sum of the outputs' values
   */
  @Benchmark
  public long reactorPublishOn(Batch batch, ReactorPublishOn reactor) {
    for (Packet packet : batch.packets) {
      Sinks.EmitResult result = reactor.sink.tryEmitNext(packet);
      if (result.isFailure()) {
        throw new IllegalStateException("Reactor refused the packet: " + result);
      }
    }
    reactor.expected += BATCH;
    return reactor.arrivals.await(reactor.expected);
  }

  /**
   * Disruptor: publish the batch into the ring, wait for its outputs.
   *
   * @param batch the packets
   * @param disruptor the ring
   * @return the sum of the outputs' values
   */
  @Benchmark
  public long disruptor(Batch batch, LmaxDisruptor disruptor) {
    RingBuffer<Slot> ring = disruptor.ring;
    for (Packet packet : batch.packets) {
      long sequence = ring.next();
      ring.get(sequence).packet = packet;
      ring.publish(sequence);
    }
    disruptor.expected += BATCH;
    return disruptor.arrivals.await(disruptor.expected);
  }
}

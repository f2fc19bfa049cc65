package dev.prime.bench;

import dev.prime.bench.PacketBlocks.Add;
import java.util.concurrent.TimeUnit;
import org.openjdk.jmh.annotations.Benchmark;
import org.openjdk.jmh.annotations.BenchmarkMode;
import org.openjdk.jmh.annotations.Fork;
import org.openjdk.jmh.annotations.Level;
import org.openjdk.jmh.annotations.Measurement;
import org.openjdk.jmh.annotations.Mode;
import org.openjdk.jmh.annotations.OutputTimeUnit;
import org.openjdk.jmh.annotations.Scope;
import org.openjdk.jmh.annotations.Setup;
import org.openjdk.jmh.annotations.State;
import org.openjdk.jmh.annotations.TearDown;
import org.openjdk.jmh.annotations.Warmup;
import reactor.core.Disposable;
import reactor.core.publisher.Flux;
import reactor.core.publisher.Sinks;

/**
 * The synchronous experiment on the peers a JVM user would pick instead of Prime chains: the same
 * blocks ({@link Add}, as many as {@link Shape#length}) as a Kotlin Flow and as a Project Reactor
 * pipeline, each assembled once and driven on the caller's thread, one packet at a time.
 */
@BenchmarkMode(Mode.AverageTime)
@OutputTimeUnit(TimeUnit.NANOSECONDS)
@Warmup(iterations = 5, time = 1)
@Measurement(iterations = 5, time = 1)
@Fork(2)
public class SyncPeerBenchmark {

  /** The blocks as a cold Kotlin Flow with one {@code map} per block. */
  @State(Scope.Thread)
  public static class KotlinFlow {
    /** The flow. */
    public FlowChain flow;

    /**
     * @param shape the parameters
     */
    @Setup(Level.Trial)
    public void build(Shape shape) {
      flow = new FlowChain(ChainShapes.directAdders(shape.length));
    }
  }

  /**
   * The blocks as a Reactor pipeline: a unicast sink, one {@code map} per block and a subscriber
   * that keeps the last output. With no scheduler in it, emitting runs the whole pipeline on the
   * emitting thread before {@code tryEmitNext} returns.
   */
  @State(Scope.Thread)
  public static class Reactor {
    /** Where the benchmark emits. */
    public Sinks.Many<Packet> sink;

    /** The last output. */
    public Packet output;

    private Disposable subscription;

    /**
     * @param shape the parameters
     */
    @Setup(Level.Trial)
    public void build(Shape shape) {
      sink = Sinks.many().unicast().onBackpressureBuffer();
      Flux<Packet> pipeline = sink.asFlux();
      for (Add adder : ChainShapes.directAdders(shape.length)) {
        pipeline = pipeline.map(adder::process);
      }
      subscription = pipeline.subscribe(packet -> output = packet);
    }

    /** Ends the subscription. */
    @TearDown(Level.Trial)
    public void close() {
      sink.tryEmitComplete();
      subscription.dispose();
    }
  }

  /**
   * Kotlin Flow: collect the flow once for one packet.
   *
   * @param input the packet
   * @param flow the flow
   * @return the output's value
   */
  @Benchmark
  public long kotlinFlow(SyncChainBenchmark.Input input, KotlinFlow flow) {
    return flow.flow.transmit(input.packet).value;
  }

  /**
   * Reactor: emit one packet and read the subscriber's output.
   *
   * @param input the packet
   * @param reactor the pipeline
   * @return the output's value
   */
  @Benchmark
  public long reactor(SyncChainBenchmark.Input input, Reactor reactor) {
    Sinks.EmitResult result = reactor.sink.tryEmitNext(input.packet);
    if (result.isFailure()) {
      throw new IllegalStateException("Reactor refused the packet: " + result);
    }
    return reactor.output.value;
  }
}

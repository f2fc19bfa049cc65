package dev.prime.bench;

import dev.prime.Block;
import dev.prime.CoreConfig;
import dev.prime.bench.PacketBlocks.Add;
import dev.prime.liberty.LibertyCore;
import java.util.concurrent.TimeUnit;
import org.openjdk.jmh.annotations.Benchmark;
import org.openjdk.jmh.annotations.BenchmarkMode;
import org.openjdk.jmh.annotations.Fork;
import org.openjdk.jmh.annotations.Level;
import org.openjdk.jmh.annotations.Measurement;
import org.openjdk.jmh.annotations.Mode;
import org.openjdk.jmh.annotations.OutputTimeUnit;
import org.openjdk.jmh.annotations.Param;
import org.openjdk.jmh.annotations.Scope;
import org.openjdk.jmh.annotations.Setup;
import org.openjdk.jmh.annotations.State;
import org.openjdk.jmh.annotations.TearDown;
import org.openjdk.jmh.annotations.Warmup;
import org.openjdk.jmh.infra.BenchmarkParams;

/**
 * What metrics cost on the Liberty row of the synchronous experiment: the same chain of adding
 * blocks called directly ({@code forLoop}, the baseline), on a Liberty core with metrics off (the
 * default: nothing is compiled in, so it must match the plain Liberty row) and with metrics on
 * (a tap per block: two {@code System.nanoTime()} reads and a few counter additions each).
 *
 * <p>Each benchmark method runs in forks of its own, so the off row's JVM never loads a tap.
 */
@BenchmarkMode(Mode.AverageTime)
@OutputTimeUnit(TimeUnit.NANOSECONDS)
@Warmup(iterations = 5, time = 1)
@Measurement(iterations = 5, time = 1)
@Fork(2)
@State(Scope.Thread)
public class MetricsOverheadBenchmark {
  /** Blocks in the chain. */
  @Param({"4"})
  public int length;

  /** The packet's size in bytes. */
  @Param({"100"})
  public int payload;

  private Packet packet;
  private Add[] adders;
  private LibertyCore core;
  private Block<Packet, Packet> chain;

  /**
   * Builds the packet and the blocks; the core of the row that needs one.
   *
   * @param metricsOn whether the Liberty core meters (null for the FOR row: no core)
   */
  private void build(Boolean metricsOn) {
    packet = Packet.ofSize(payload);
    adders = ChainShapes.directAdders(length);
    if (metricsOn != null) {
      core = new LibertyCore(CoreConfig.builder().metrics(metricsOn).build());
      chain = ChainShapes.adders(core, length);
      core.start();
    }
  }

  /**
   * Builds what the running benchmark method needs.
   *
   * @param params tells which method runs
   */
  @Setup(Level.Trial)
  public void setUp(BenchmarkParams params) {
    String method = params.getBenchmark();
    build(method.endsWith("forLoop") ? null : method.endsWith("libertyMetricsOn"));
  }

  /** Closes the core. */
  @TearDown(Level.Trial)
  public void close() {
    if (core != null) {
      core.close();
    }
  }

  /**
   * The baseline: the blocks called in a loop.
   *
   * @return the result, for JMH
   */
  @Benchmark
  public Packet forLoop() {
    return ChainShapes.runDirect(adders, packet);
  }

  /**
   * Liberty with metrics off (the default).
   *
   * @return the result, for JMH
   */
  @Benchmark
  public Packet libertyMetricsOff() {
    return chain.process(packet);
  }

  /**
   * Liberty with metrics on.
   *
   * @return the result, for JMH
   */
  @Benchmark
  public Packet libertyMetricsOn() {
    return chain.process(packet);
  }
}

package dev.prime.bench;

import java.util.concurrent.TimeUnit;
import org.openjdk.jmh.annotations.Benchmark;
import org.openjdk.jmh.annotations.BenchmarkMode;
import org.openjdk.jmh.annotations.Fork;
import org.openjdk.jmh.annotations.Measurement;
import org.openjdk.jmh.annotations.Mode;
import org.openjdk.jmh.annotations.OutputTimeUnit;
import org.openjdk.jmh.annotations.Threads;
import org.openjdk.jmh.annotations.Warmup;

/**
 * The paper's asynchronous mode for chains: one chain per core, every core busy at once, each
 * chain fed its next packet as soon as it returns the previous output (data flows constantly).
 * The chains and packets are the synchronous experiment's ({@link SyncChainBenchmark}'s states
 * are per thread, so every thread has its own chain); the time is per transmission of one
 * thread. Run it with {@code -p scenario=monomorphic}: the table's runner does.
 */
@BenchmarkMode(Mode.AverageTime)
@OutputTimeUnit(TimeUnit.NANOSECONDS)
@Warmup(iterations = 5, time = 1)
@Measurement(iterations = 5, time = 1)
@Fork(2)
@Threads(Threads.MAX)
public class AsyncChainBenchmark {

  /**
   * FOR: the blocks called directly, written out for the 4-block chain.
   *
   * @param input the packet
   * @param blocks the blocks
   * @return the output's value
   */
  @Benchmark
  public long forHandWritten(SyncChainBenchmark.Input input, SyncChainBenchmark.Direct blocks) {
    return blocks.a4.process(blocks.a3.process(blocks.a2.process(blocks.a1.process(input.packet))))
        .value;
  }

  /**
   * Liberty chains, one per core.
   *
   * @param input the packet
   * @param chain the chain
   * @return the output's value
   */
  @Benchmark
  public long liberty(SyncChainBenchmark.Input input, SyncChainBenchmark.Liberty chain) {
    return chain.chain.process(input.packet).value;
  }

  /**
   * Radiant chains, one per core.
   *
   * @param input the packet
   * @param chain the chain
   * @return the output's value
   */
  @Benchmark
  public long radiant(SyncChainBenchmark.Input input, SyncChainBenchmark.Radiant chain) {
    return chain.chain.process(input.packet).value;
  }
}

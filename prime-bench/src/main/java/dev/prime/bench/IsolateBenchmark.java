package dev.prime.bench;

import dev.prime.Block;
import dev.prime.liberty.LibertyCore;
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
import org.openjdk.jmh.annotations.Threads;
import org.openjdk.jmh.annotations.Warmup;

/**
 * What {@link dev.prime.PrimeCore#isolate} adds to a call on Liberty: a chain of one small block
 * called directly ({@code baseline}), through an isolated chain's user with no other caller
 * ({@code isolated}), and by two threads at once, which then take turns ({@code
 * isolatedTwoThreads}: the time per call of each thread, so about twice the time one call holds
 * the chain).
 */
@BenchmarkMode(Mode.AverageTime)
@OutputTimeUnit(TimeUnit.NANOSECONDS)
@Warmup(iterations = 5, time = 1)
@Measurement(iterations = 5, time = 1)
@Fork(2)
public class IsolateBenchmark {

  /** Adds one, within the small integers the JDK caches (so no call allocates). */
  private static final Block<Integer, Integer> NEXT = x -> (x + 1) & 63;

  /** A Liberty core with the block as a plain chain and as an isolated chain's user. */
  @State(Scope.Benchmark)
  public static class Chains {
    /** The block as a plain chain. */
    public Block<Integer, Integer> plain;

    /** The block shared through {@code isolate}, called through one user. */
    public Block<Integer, Integer> isolated;

    private LibertyCore core;

    /** Builds and starts the core. */
    @Setup(Level.Trial)
    public void build() {
      core = new LibertyCore();
      plain = core.chain(NEXT).toBlock();
      isolated = core.isolate(core.chain(NEXT)).newUser().toBlock();
      core.start();
    }

    /** Closes the core. */
    @TearDown(Level.Trial)
    public void close() {
      core.close();
    }
  }

  /** Each thread's last value, fed to its next call. */
  @State(Scope.Thread)
  public static class Value {
    /** The last value. */
    public int value;
  }

  /**
   * The plain chain.
   *
   * @param chains the chains
   * @param last the thread's value
   * @return the next value
   */
  @Benchmark
  public int baseline(Chains chains, Value last) {
    return last.value = chains.plain.process(last.value);
  }

  /**
   * The isolated chain, one caller.
   *
   * @param chains the chains
   * @param last the thread's value
   * @return the next value
   */
  @Benchmark
  public int isolated(Chains chains, Value last) {
    return last.value = chains.isolated.process(last.value);
  }

  /**
   * The isolated chain, two callers taking turns.
   *
   * @param chains the chains
   * @param last the thread's value
   * @return the next value
   */
  @Benchmark
  @Threads(2)
  public int isolatedTwoThreads(Chains chains, Value last) {
    return last.value = chains.isolated.process(last.value);
  }
}

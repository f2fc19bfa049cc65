package dev.prime.bench;

import java.lang.management.ManagementFactory;
import java.lang.management.ThreadMXBean;
import java.util.Collection;
import java.util.List;
import org.openjdk.jmh.annotations.Level;
import org.openjdk.jmh.annotations.Scope;
import org.openjdk.jmh.annotations.Setup;
import org.openjdk.jmh.annotations.State;
import org.openjdk.jmh.annotations.TearDown;
import org.openjdk.jmh.infra.BenchmarkParams;
import org.openjdk.jmh.infra.IterationParams;
import org.openjdk.jmh.profile.InternalProfiler;
import org.openjdk.jmh.results.AggregationPolicy;
import org.openjdk.jmh.results.IterationResult;
import org.openjdk.jmh.results.Result;
import org.openjdk.jmh.results.ScalarResult;

/**
 * CPU time per operation of a single-threaded benchmark: a figure that, unlike JMH's wall-clock
 * score, does not grow when other processes take the cores away (a shared 2-core machine under a
 * load of 10 stretches wall-clock scores several-fold and unevenly). Select it with
 * {@code -prof dev.prime.bench.WorkerCpuTime}; it adds {@code cpu.time.norm} (ns/op) to every
 * benchmark that takes a {@link Clock} state.
 *
 * <p>The clock reads the benchmark thread's CPU time after every per-iteration setup it depends
 * on (the polluting chains, the megamorphic site) and before the per-iteration teardown; the
 * profiler divides it by the operations the thread ran in between (JMH's {@code allOps}).
 */
public final class WorkerCpuTime implements InternalProfiler {
  private static final ThreadMXBean THREADS = ManagementFactory.getThreadMXBean();
  private static volatile long lastIterationNanos = -1;

  /** Created by JMH. */
  public WorkerCpuTime() {}

  /** Measures the benchmark thread's CPU time between setup and teardown of each iteration. */
  @State(Scope.Thread)
  public static class Clock {
    private long startNanos;

    /**
     * Starts after the setups that drive polluting code.
     *
     * @param shape the parameters (its per-iteration setup runs first)
     * @param site the megamorphic baseline (its per-iteration setup runs first)
     */
    @Setup(Level.Iteration)
    public void start(Shape shape, SyncChainBenchmark.Megamorphic site) {
      startNanos = THREADS.getCurrentThreadCpuTime();
    }

    /** Stops before any per-iteration teardown. */
    @TearDown(Level.Iteration)
    public void stop() {
      lastIterationNanos = THREADS.getCurrentThreadCpuTime() - startNanos;
    }
  }

  /**
   * The same clock for benchmarks without {@link Shape} or the megamorphic site (such as {@link
   * RecordingOverheadBenchmark}): no per-iteration setup runs before it.
   */
  @State(Scope.Thread)
  public static class PlainClock {
    private long startNanos;

    /** Starts the iteration's CPU time. */
    @Setup(Level.Iteration)
    public void start() {
      startNanos = THREADS.getCurrentThreadCpuTime();
    }

    /** Stops before any per-iteration teardown. */
    @TearDown(Level.Iteration)
    public void stop() {
      lastIterationNanos = THREADS.getCurrentThreadCpuTime() - startNanos;
    }
  }

  @Override
  public String getDescription() {
    return "CPU time of the benchmark thread per operation (ns/op), for single-threaded benchmarks";
  }

  @Override
  public void beforeIteration(BenchmarkParams benchmark, IterationParams iteration) {
    lastIterationNanos = -1;
  }

  @Override
  @SuppressWarnings("rawtypes") // JMH's interface declares the raw type
  public Collection<? extends Result> afterIteration(
      BenchmarkParams benchmark, IterationParams iteration, IterationResult result) {
    long nanos = lastIterationNanos;
    long ops = result.getMetadata().getAllOps();
    if (nanos < 0 || ops <= 0) {
      return List.of();
    }
    return List.of(
        new ScalarResult("cpu.time.norm", (double) nanos / ops, "ns/op", AggregationPolicy.AVG));
  }
}

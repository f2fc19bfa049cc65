package dev.prime.bench;

import dev.prime.optimus.RecentIds;
import java.util.ArrayDeque;
import java.util.HashSet;
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
import org.openjdk.jmh.annotations.Warmup;

/**
 * What an Optimus service or reader pays per value to skip duplicates: a lookup of the value's id
 * among the last 4096 it handled, then adding it (the oldest id falls out). {@code consecutive}:
 * ids come as a producer's counter makes them, one after the other from a random start (a
 * source's values, and a service's one output per input, which keeps its input's id). {@code
 * scattered}: every id mixed, unrelated to the one before (a service's several outputs per input).
 *
 * <p>{@code baseline}: the same with a {@code HashSet<Long>} and a queue of the ids in order,
 * what a set of boxed ids costs. {@code recentIds}: the primitive set the services and readers
 * use (prime-optimus, internal; called here for measurement only).
 */
@BenchmarkMode(Mode.AverageTime)
@OutputTimeUnit(TimeUnit.NANOSECONDS)
@Warmup(iterations = 3, time = 1)
@Measurement(iterations = 5, time = 1)
@Fork(2)
public class RecentIdsBenchmark {
  private static final int CAPACITY = 4096;

  /** A full set of each kind and the next id. */
  @State(Scope.Thread)
  public static class Sets {
    /** How the ids follow each other. */
    @Param({"consecutive", "scattered"})
    public String ids;

    RecentIds recent;
    HashSet<Long> boxed;
    ArrayDeque<Long> order;
    long next;
    private boolean scattered;

    /**
     * The next id.
     *
     * @return a counter's next value, mixed if the ids are scattered
     */
    long nextId() {
      long id = next++;
      if (!scattered) {
        return id;
      }
      id = (id ^ (id >>> 33)) * 0xff51afd7ed558ccdL;
      id = (id ^ (id >>> 33)) * 0xc4ceb9fe1a85ec53L;
      return id ^ (id >>> 33);
    }

    /** Fills both sets with 4096 ids. */
    @Setup(Level.Trial)
    public void fill() {
      recent = new RecentIds(CAPACITY);
      boxed = new HashSet<>();
      order = new ArrayDeque<>();
      next = new java.util.Random(42).nextLong();
      scattered = ids.equals("scattered");
      for (int i = 0; i < CAPACITY; i++) {
        long id = nextId();
        recent.add(id);
        boxed.add(id);
        order.add(id);
      }
    }
  }

  /**
   * A lookup and an add in a set of boxed ids.
   *
   * @param sets the state
   * @return whether the id was there
   */
  @Benchmark
  public boolean baseline(Sets sets) {
    long id = sets.nextId();
    boolean seen = sets.boxed.contains(id);
    if (!seen && sets.boxed.add(id)) {
      sets.order.add(id);
      sets.boxed.remove(sets.order.poll());
    }
    return seen;
  }

  /**
   * A lookup and an add in the primitive set.
   *
   * @param sets the state
   * @return whether the id was there
   */
  @Benchmark
  public boolean recentIds(Sets sets) {
    long id = sets.nextId();
    boolean seen = sets.recent.contains(id);
    if (!seen) {
      sets.recent.add(id);
    }
    return seen;
  }
}

package dev.prime.bench;

import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicLong;

/**
 * Where the consumer of a thread hand-off reports each output, and where the producing benchmark
 * thread waits for a whole batch to come out.
 *
 * <p>Design: one consumer thread calls {@link #arrive}; the count is an {@link AtomicLong}
 * written after the sum, so a producer that sees the count also sees the sum of those outputs.
 * The producer spins ({@link Thread#onSpinWait}) for {@link #SPIN_NANOS} of the clock, as a
 * latency-minded caller of Reactor, Kotlin Channels or the Disruptor would, then yields its core
 * between checks, so that on a machine with more runnable threads than cores the waiting producer
 * does not starve the consumer it waits for. The spin is timed, not counted: one
 * {@code onSpinWait} takes from a few to about 90 ns depending on the CPU (1000 rounds were
 * 56–90 µs on the AMD EPYC the results were taken on, long enough to hold a shared core from the
 * consumer for most of a batch). It gives up with an exception after {@link #TIMEOUT_SECONDS} so a
 * broken pipeline fails the benchmark instead of hanging it.
 */
public final class Arrivals {
  /** How long {@link #await} waits for a batch before it fails. */
  public static final long TIMEOUT_SECONDS = 30;

  /**
   * How long the producer busy-waits before it starts yielding, in nanoseconds: 2,000 (2 µs, what
   * the Prime sources' own readers spin), or the system property {@code dev.prime.bench.spinNanos}
   * (e.g. {@code -jvmArgsAppend -Ddev.prime.bench.spinNanos=60000000000} to spin only).
   */
  public static final long SPIN_NANOS = Long.getLong("dev.prime.bench.spinNanos", 2_000);

  /** Spin rounds between two reads of the clock. */
  private static final int ROUNDS_PER_CLOCK_READ = 8;

  private final AtomicLong count = new AtomicLong();
  private volatile long sum;

  /** Creates a counter at zero. */
  public Arrivals() {}

  /**
   * Counts one output. Called by the single consumer thread only.
   *
   * @param value the output's value, summed so it is consumed
   */
  public void arrive(long value) {
    sum += value;
    count.incrementAndGet();
  }

  /**
   * How many outputs arrived so far.
   *
   * @return the count
   */
  public long count() {
    return count.get();
  }

  /**
   * Waits until at least {@code target} outputs have arrived.
   *
   * @param target the count to reach
   * @return the sum of the outputs' values so far (give it to JMH)
   * @throws IllegalStateException if they do not arrive within {@link #TIMEOUT_SECONDS}
   */
  public long await(long target) {
    if (count.get() >= target) {
      return sum;
    }
    long deadline = 0;
    long spinUntil = System.nanoTime() + SPIN_NANOS;
    boolean spinning = true;
    int rounds = 0;
    int checks = 0;
    while (count.get() < target) {
      if (spinning) {
        Thread.onSpinWait();
        if (++rounds == ROUNDS_PER_CLOCK_READ) {
          rounds = 0;
          spinning = System.nanoTime() - spinUntil < 0;
        }
      } else {
        Thread.yield();
      }
      if (++checks == 1 << 14) {
        checks = 0;
        long now = System.nanoTime();
        if (deadline == 0) {
          deadline = now + TimeUnit.SECONDS.toNanos(TIMEOUT_SECONDS);
        } else if (now - deadline > 0) {
          throw new IllegalStateException(
              "only " + count.get() + " of " + target + " outputs arrived within "
                  + TIMEOUT_SECONDS + " s: the consumer thread is stuck or failed");
        }
      }
    }
    return sum;
  }
}

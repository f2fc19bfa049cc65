package dev.prime.faults;

import java.time.Duration;
import java.util.concurrent.locks.LockSupport;
import java.util.function.BooleanSupplier;

/**
 * Waits for a state outside this JVM (keys in Redis, a process's lease) that nothing can signal:
 * checks it every {@link #STEP}, at most until a deadline, so the loop is bounded in time and
 * count. Used only where no latch can exist; events inside the JVM use latches.
 */
final class Bounded {
  static final Duration STEP = Duration.ofMillis(50);

  private Bounded() {}

  /**
   * Checks {@code condition} until it holds or {@code timeout} passed.
   *
   * @return the nanoseconds it took, or -1 if it never held
   */
  static long await(Duration timeout, BooleanSupplier condition) {
    long start = System.nanoTime();
    long checks = timeout.toNanos() / STEP.toNanos() + 1;
    for (long i = 0; i <= checks; i++) {
      if (condition.getAsBoolean()) return System.nanoTime() - start;
      if (System.nanoTime() - start > timeout.toNanos()) break;
      LockSupport.parkNanos(STEP.toNanos());
    }
    return condition.getAsBoolean() ? System.nanoTime() - start : -1;
  }

  /** Lets a fault last {@code duration}: the outage itself, not a synchronisation. */
  static void hold(Duration duration) {
    long end = System.nanoTime() + duration.toNanos();
    for (int i = 0; i < 100_000; i++) {
      long left = end - System.nanoTime();
      if (left <= 0) return;
      LockSupport.parkNanos(left);
    }
  }
}

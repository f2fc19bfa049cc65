package dev.prime.internal;

import java.time.Duration;

/**
 * Timeouts as nanoseconds that a deadline can be made of. A {@link Duration} may be far longer than
 * a {@code long} of nanoseconds holds (the builders accept {@code Duration.ofSeconds(Long.MAX_VALUE)}
 * as "as long as it takes"), and {@code System.nanoTime() + timeout.toNanos()} would then throw or
 * overflow into the past.
 */
public final class Deadlines {
  /** The longest timeout in nanoseconds: {@code Long.MAX_VALUE / 2}, about 146 years. */
  public static final long LONGEST_NANOS = Long.MAX_VALUE / 2;

  private Deadlines() {}

  /**
   * {@return {@code timeout} in nanoseconds, at most {@link #LONGEST_NANOS}, so that {@code
   * System.nanoTime()} plus it, or twice it, does not overflow}
   *
   * @param timeout a timeout that is not negative
   */
  public static long boundedNanos(Duration timeout) {
    try {
      return Math.min(timeout.toNanos(), LONGEST_NANOS);
    } catch (ArithmeticException longerThanALongHolds) {
      return LONGEST_NANOS;
    }
  }
}

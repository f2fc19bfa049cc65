package dev.prime;

import java.time.Instant;
import java.util.Objects;

/**
 * One tick of a timer ({@link PrimeCore#timer(String, java.time.Duration)}).
 *
 * @param count 1 for the timer's first tick, 2 for the next, ...: a gap never happens, since a
 *     timer that falls behind catches up (see {@link PrimeCore#timer})
 * @param time when the tick was due by the core's clock ({@link PrimeClock#now()} when the timer
 *     began, plus {@code count} periods), not when it was published: ticks of a timer are exactly
 *     one period apart
 */
public record Tick(long count, Instant time) {
  /**
   * Checks the components.
   *
   * @param count 1 or more
   * @param time when the tick was due
   */
  public Tick {
    if (count < 1) {
      throw new IllegalArgumentException("tick counts start at 1, not " + count);
    }
    Objects.requireNonNull(time, "time");
  }
}

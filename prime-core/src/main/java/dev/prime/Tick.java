package dev.prime;

import java.time.Instant;
import java.util.Objects;

/**
 * One tick of a timer ({@link PrimeCore#timer(String, java.time.Duration)}).
 *
 * @param count 1 for the timer's first tick, 2 for the next, ...: the timer numbers every tick
 *     and skips none when it falls behind, since it catches up (see {@link PrimeCore#timer}); what
 *     reads its ticks still misses the count of a tick whose publish failed, which is not retried,
 *     and a plain reader those its retention dropped ({@link Reader#missed()})
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

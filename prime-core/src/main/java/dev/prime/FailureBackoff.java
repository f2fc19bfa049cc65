package dev.prime;

import java.time.Duration;

/**
 * The wait after failures in a row that the core's own loops share (a generic service's default
 * {@link GenericService#backoff}, a timer whose clock fails): doubling from 10 ms up to 1 s, so a
 * failure that lasts neither spins a core nor floods the error handler.
 */
final class FailureBackoff {
  private FailureBackoff() {}

  /**
   * {@return the wait after {@code failures} failures in a row: 10 ms, 20 ms, 40 ms, ..., 640 ms,
   * 1 s, 1 s, ...; a count below 1 counts as 1}
   *
   * @param failures how many failed in a row
   */
  static Duration after(int failures) {
    int doublings = Math.min(Math.max(failures, 1) - 1, 10);
    return Duration.ofMillis(Math.min(10L << doublings, 1000L));
  }
}

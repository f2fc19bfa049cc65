package dev.prime.inspector.internal;

/**
 * The time between two samples of a figures source, for rates: {@link #secondsSinceLast()} is 0
 * on the first sample (no rate yet). Used by one sampling thread at a time.
 */
final class SamplingClock {
  private long lastNanos;

  /** {@return the seconds since the previous call, or 0 on the first call} */
  double secondsSinceLast() {
    long now = System.nanoTime();
    double seconds = lastNanos == 0 ? 0 : (now - lastNanos) / 1e9;
    lastNanos = now;
    return seconds;
  }
}

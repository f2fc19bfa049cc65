package dev.prime;

/**
 * Told of every value a metered node processed, with its time: for metrics libraries that keep
 * their own histograms (Micrometer's {@code Timer}). Register one with {@link
 * Metrics#onProcessed(String, ProcessingListener)}.
 *
 * <p>Called on the thread that processed the value, right after it (before a chain's output goes
 * on), so it must be quick and must not block or throw; what it throws is caught and logged
 * (rate-limited), and the value goes on.
 */
@FunctionalInterface
public interface ProcessingListener {
  /**
   * One value was processed.
   *
   * @param nanos how long it took, in nanoseconds (the time {@link ServiceMetrics#processing()}
   *     counted)
   * @param failed whether the node's logic threw on it
   */
  void processed(long nanos, boolean failed);
}

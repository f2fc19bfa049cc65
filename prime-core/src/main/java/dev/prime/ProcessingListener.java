package dev.prime;

/**
 * Told of every value a metered node processed, with its time: for metrics libraries that keep
 * their own histograms (Micrometer's {@code Timer}). Register one with {@link
 * Metrics#onProcessed(String, ProcessingListener)}.
 *
 * <p>Called on the thread that processed the value, right after it (before a chain's output goes
 * on), so it must be quick and must not block or throw; what it throws (an exception, checked or
 * not, or an {@link Error} but a {@link VirtualMachineError}) is caught and logged, and the value
 * goes on. The log is rate-limited per node, as the default error handler's is: the first
 * failure of a burst in full, then one WARN line per 10 s counting the rest, and the count still
 * owed when the core closes.
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

package dev.prime.inspector.internal;

/**
 * What the page shows under one box: how many values per second, how long one takes, how many
 * failed. A figure its source does not have is {@code NaN} (latency) or {@code -1} (counts), and
 * the page leaves it out.
 *
 * @param rate values per second over the last sampling period
 * @param total values so far
 * @param latencyMillis mean processing time over the last period (when idle: since the start), in
 *     milliseconds, or NaN
 * @param errors failures so far, or -1
 * @param deadLetters values the media set aside, or -1
 * @param queueDepth values waiting in the node's input now, or -1 (no queue, or see {@code
 *     queueUnknown})
 * @param queueUnknown the node has an input queue whose depth the media cannot read now (Optimus
 *     while Redis is unreachable); {@code queueDepth} is then -1
 * @param missed values the node's input missed, or -1
 */
public record NodeFigures(
    double rate,
    long total,
    double latencyMillis,
    long errors,
    long deadLetters,
    long queueDepth,
    boolean queueUnknown,
    long missed) {

  /** Figures with a rate and a total only. */
  static NodeFigures counted(double rate, long total) {
    return new NodeFigures(rate, total, Double.NaN, -1, -1, -1, false, -1);
  }
}

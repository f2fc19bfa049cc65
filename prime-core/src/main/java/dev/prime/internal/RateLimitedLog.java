package dev.prime.internal;

import java.util.Map;
import java.util.Objects;
import java.util.concurrent.ConcurrentHashMap;
import java.util.function.LongSupplier;
import org.slf4j.Logger;
import org.slf4j.LoggerFactory;

/**
 * Logs a repeated event per key without flooding the log: the first event of a burst is logged in
 * full by the caller (with its stack trace, say); the following ones are counted and summarised in
 * at most one WARN line per interval ("...: 37 more in the last 10 s; the last: ..."); once a key
 * has been quiet for the quiet period, its next event starts a new burst and is logged in full
 * again. A summary still owed when a burst ends is written at that key's next event, or by {@link
 * #flush()}. Used by the default error handler, by media for missed values and dead letters, by
 * combinators for dropped values and by metrics for failing listeners.
 *
 * <p>Design note: thread-safe, one small state object per key (its monitor guards it), no timer
 * thread: summaries are written by the thread that records an event. Log calls are made outside
 * the monitor. Memory grows with the number of distinct keys only, so keys are fixed names (a
 * service, a source), never values.
 */
public final class RateLimitedLog {

  /** The default interval between summary lines of one key and the quiet period, in seconds. */
  public static final long DEFAULT_SECONDS = 10;

  private final Logger log;
  private final long intervalNanos;
  private final long quietNanos;
  private final LongSupplier nanoClock;
  private final Map<String, Burst> bursts = new ConcurrentHashMap<>();

  /**
   * A log summarising every {@value #DEFAULT_SECONDS} s, with a new burst after {@value
   * #DEFAULT_SECONDS} s without events.
   *
   * @param loggerName the SLF4J logger the summaries go to (the caller's own, usually)
   */
  public RateLimitedLog(String loggerName) {
    this(loggerName, DEFAULT_SECONDS * 1_000_000_000L, DEFAULT_SECONDS * 1_000_000_000L, System::nanoTime);
  }

  /**
   * @param loggerName the SLF4J logger the summaries go to
   * @param intervalNanos the least time between two summary lines of one key
   * @param quietNanos how long a key has no events before its next one starts a new burst
   * @param nanoClock the clock, {@link System#nanoTime()} but in tests
   */
  public RateLimitedLog(
      String loggerName, long intervalNanos, long quietNanos, LongSupplier nanoClock) {
    this.log = LoggerFactory.getLogger(Objects.requireNonNull(loggerName, "loggerName"));
    if (intervalNanos <= 0 || quietNanos <= 0) {
      throw new IllegalArgumentException(
          "interval and quiet period must be positive, not " + intervalNanos + " and " + quietNanos);
    }
    this.intervalNanos = intervalNanos;
    this.quietNanos = quietNanos;
    this.nanoClock = Objects.requireNonNull(nanoClock, "nanoClock");
  }

  /**
   * Records {@code count} events of {@code key}.
   *
   * @param key what happened, a fixed phrase such as {@code service 'odometry' failed}
   * @param count how many events (values missed, say); at least 1
   * @param detail the latest event in a few words, for the summary
   * @param logFirst logs the first event of a burst in full; run on this thread, outside locks
   */
  public void record(String key, long count, String detail, Runnable logFirst) {
    long now = nanoClock.getAsLong();
    Burst burst = bursts.computeIfAbsent(key, k -> new Burst());
    long owed;
    long owedNanos;
    String owedDetail;
    boolean first;
    synchronized (burst) {
      owed = 0;
      owedNanos = 0;
      owedDetail = null;
      first = !burst.started || now - burst.lastEvent >= quietNanos;
      if (first) {
        if (burst.counted > 0) { // the end of the previous burst
          owed = burst.counted;
          owedNanos = burst.lastEvent - burst.lastSummary;
          owedDetail = burst.lastDetail;
        }
        burst.started = true;
        burst.counted = 0;
        burst.lastSummary = now;
      } else {
        burst.counted += count;
        burst.lastDetail = detail;
        if (now - burst.lastSummary >= intervalNanos) {
          owed = burst.counted;
          owedNanos = now - burst.lastSummary;
          owedDetail = detail;
          burst.counted = 0;
          burst.lastSummary = now;
        }
      }
      burst.lastEvent = now;
    }
    if (owed > 0) {
      summarise(key, owed, owedNanos, owedDetail);
    }
    if (first) {
      logFirst.run();
    }
  }

  /** Writes the summary every key still owes (at close, say). */
  public void flush() {
    bursts.forEach(
        (key, burst) -> {
          long owed;
          long owedNanos;
          String owedDetail;
          synchronized (burst) {
            owed = burst.counted;
            owedNanos = burst.lastEvent - burst.lastSummary;
            owedDetail = burst.lastDetail;
            burst.counted = 0;
            burst.lastSummary = burst.lastEvent;
          }
          if (owed > 0) {
            summarise(key, owed, owedNanos, owedDetail);
          }
        });
  }

  private void summarise(String key, long count, long nanos, String detail) {
    log.warn(
        "{}: {} more in the last {} s; the last: {}",
        key,
        count,
        Math.max(1, (nanos + 999_999_999L) / 1_000_000_000L),
        detail);
  }

  private static final class Burst {
    boolean started;
    long lastEvent;
    long lastSummary;
    long counted;
    String lastDetail;
  }
}

package dev.prime;

import dev.prime.internal.RateLimitedLog;
import java.util.Arrays;
import java.util.concurrent.atomic.AtomicLongArray;
import java.util.concurrent.atomic.LongAccumulator;
import java.util.concurrent.atomic.LongAdder;
import java.util.function.LongSupplier;
import org.slf4j.Logger;
import org.slf4j.LoggerFactory;

/**
 * The counters of one metered node (see {@link Metrics}), updated by the taps {@link
 * MeteringPoints} compiles into it.
 *
 * <p>Design note. Updated on whatever threads run the node (a chain may be called from many at
 * once), read by snapshots on any thread, never locked: counts are {@link LongAdder}s, the
 * largest time a {@link LongAccumulator} (which writes only when the value grows), the buckets an
 * {@link AtomicLongArray}. Listeners are a copy-on-write array in a volatile field: one volatile
 * read per value, no allocation. A snapshot reads the counters one after another; the
 * histogram's count is the sum of its buckets, so it is consistent in itself.
 */
final class ServiceMeter {
  private static final ProcessingListener[] NO_LISTENERS = {};
  private static final Logger LOG = LoggerFactory.getLogger(ProcessingListener.class);

  private final String name;
  private final String kind;
  private final RateLimitedLog listenerFailures; // the core's: flushed when it closes
  private final LongAdder in = new LongAdder();
  private final LongAdder out = new LongAdder();
  private final LongAdder failures = new LongAdder();
  private final LongAdder totalNanos = new LongAdder();
  private final LongAccumulator maxNanos = new LongAccumulator(Math::max, 0);
  private final AtomicLongArray buckets = new AtomicLongArray(ProcessingTimes.bucketCount());
  private volatile ProcessingListener[] listeners = NO_LISTENERS;
  private volatile LongSupplier queue; // the node's input queue where the core has one
  private volatile LongSupplier missed; // what the node's input missed, where it can miss

  /**
   * @param name the node's name in the topology model
   * @param kind the node's kind (its class's simple name)
   * @param listenerFailures where failures of its listeners are logged: one per core, so the
   *     count a burst still owes is written when the core closes
   */
  ServiceMeter(String name, String kind, RateLimitedLog listenerFailures) {
    this.name = name;
    this.kind = kind;
    this.listenerFailures = listenerFailures;
  }

  String name() {
    return name;
  }

  /**
   * {@return whether the node's output is an event source of the media and its input no queue of
   * the media: an event source, a combinator, a timer (the media counts what its readers missed,
   * and keeps no queue or dead letters for it)}
   */
  boolean isSource() {
    return kind.equals("EventSource") || kind.equals("Combinator") || kind.equals("Timer");
  }

  /**
   * {@return whether the core runs the node on a thread of its own on every media (a generic
   * service, a combinator, a timer): the media keeps no queue or dead letters for it}
   */
  boolean runByCore() {
    return kind.equals("GenericServiceNode") || kind.equals("Combinator") || kind.equals("Timer");
  }

  /** A value went in. */
  void in() {
    in.increment();
  }

  /** A value came out. */
  void out() {
    out.increment();
  }

  /** A value was processed in {@code nanos}; {@code failed} if the logic threw. */
  void processed(long nanos, boolean failed) {
    long n = Math.max(0, nanos);
    buckets.incrementAndGet(ProcessingTimes.bucket(n));
    totalNanos.add(n);
    maxNanos.accumulate(n);
    if (failed) {
      failures.increment();
    }
    ProcessingListener[] told = listeners;
    for (ProcessingListener listener : told) {
      try {
        listener.processed(n, failed);
      } catch (VirtualMachineError e) {
        throw e; // the JVM itself is in trouble
      } catch (Throwable e) { // an Error or a checked exception (Kotlin) too: the value goes on
        listenerFailures.record(
            "a metrics listener of '" + name + "' threw",
            1,
            e.toString(),
            () -> LOG.warn("a metrics listener of '{}' threw; the value goes on", name, e));
      }
    }
  }

  /** Where the node's input queue is the core's (an in-memory service input): its depth. */
  void queue(LongSupplier depth) {
    this.queue = depth;
  }

  /** Where the core counts what the node's readers miss: how many they missed. */
  void missed(LongSupplier count) {
    this.missed = count;
  }

  /**
   * {@return the values in the core's queue for this node that it has not finished (waiting, plus
   * those it is processing), -1 if it has no such queue}
   */
  long queueDepth() {
    LongSupplier depth = queue;
    if (depth == null) {
      return -1;
    }
    long timed = 0;
    for (int i = 0; i < buckets.length(); i++) {
      timed += buckets.get(i);
    }
    return depth.getAsLong() + Math.max(0, in.sum() - timed);
  }

  synchronized void addListener(ProcessingListener listener) {
    ProcessingListener[] now = listeners;
    ProcessingListener[] more = Arrays.copyOf(now, now.length + 1);
    more[now.length] = listener;
    listeners = more;
  }

  synchronized void removeListener(ProcessingListener listener) {
    ProcessingListener[] now = listeners;
    for (int i = 0; i < now.length; i++) {
      if (now[i] == listener) {
        ProcessingListener[] fewer = new ProcessingListener[now.length - 1];
        System.arraycopy(now, 0, fewer, 0, i);
        System.arraycopy(now, i + 1, fewer, i, now.length - i - 1);
        listeners = fewer;
        return;
      }
    }
  }

  /** {@return what the node's input missed, where the core counts it; else 0} */
  long missed() {
    LongSupplier count = missed;
    return count == null ? 0 : count.getAsLong();
  }

  /**
   * Reads the counters in the reverse of the order a value updates them (in, then its time and
   * failure, then out), {@code in} last: a value a snapshot counts timed, failed or out is then
   * counted in too, as {@link ServiceMetrics} promises (one in flight may show in {@code in}
   * only, never the reverse).
   */
  ServiceMetrics snapshot(String pseudoname, long deadLetters, long queueDepth, long missed) {
    long valuesOut = out.sum();
    long failed = failures.sum();
    long[] counts = new long[buckets.length()];
    for (int i = 0; i < counts.length; i++) {
      counts[i] = buckets.get(i);
    }
    ProcessingTimes times = new ProcessingTimes(counts, totalNanos.sum(), maxNanos.get());
    long valuesIn = in.sum();
    return new ServiceMetrics(
        name, pseudoname, kind, valuesIn, valuesOut, failed, deadLetters, queueDepth, missed, times);
  }
}

package dev.prime.metrics;

import dev.prime.Metrics;
import dev.prime.ServiceMetrics;
import java.time.Duration;
import java.util.Collection;
import java.util.HashMap;
import java.util.Map;
import java.util.Objects;

/**
 * One snapshot of all of a core's metered nodes, served to the registry's reads for a refresh
 * period: a registry reading every meter takes one snapshot, not one per meter.
 *
 * <p>Design note. Guarded by its monitor: a read older than the period takes a new snapshot of
 * every node under it (on Optimus a few Redis round trips per node), so concurrent reads wait
 * for that one snapshot rather than each taking their own. A node missing from a snapshot of the
 * period (no longer metered here: another Optimus process runs it now) reads as missing until
 * the next one: were it to take a snapshot of its own, each read of its meters would take one.
 * Only binding meters of a node the snapshot lacks ({@link #cover}) ends the period early. With a
 * period of zero every read takes a snapshot of its node only, and a node that is no longer
 * metered here when it is taken reads as missing: a read never fails for a node that went away.
 */
final class SnapshotCache {
  private final Metrics metrics;
  private final long refreshNanos;
  private Map<String, ServiceMetrics> latest = Map.of(); // guarded by this
  private long takenAt; // guarded by this: System.nanoTime() of latest
  private boolean taken; // guarded by this
  private volatile long generation; // snapshots taken so far

  SnapshotCache(Metrics metrics, Duration refresh) {
    this.metrics = metrics;
    Objects.requireNonNull(refresh, "refresh must not be null");
    if (refresh.isNegative()) {
      throw new IllegalArgumentException(
          "refresh must be zero (a snapshot per read) or positive, was " + refresh);
    }
    // A period longer than a long of nanoseconds (about 292 years) is one that never ends.
    this.refreshNanos =
        refresh.compareTo(Duration.ofNanos(Long.MAX_VALUE)) >= 0 ? Long.MAX_VALUE : refresh.toNanos();
  }

  /**
   * {@return the node's metrics from a snapshot at most one refresh period old; {@code null} if
   * it is no longer metered here (its declaration failed, or another Optimus process took it
   * over)}
   */
  synchronized ServiceMetrics service(String name) {
    if (refreshNanos == 0) {
      generation++;
      // No look at the names first: the node may go away between that look and the snapshot.
      try {
        return metrics.service(name);
      } catch (IllegalArgumentException gone) {
        return null;
      }
    }
    long now = System.nanoTime();
    if (!taken || now - takenAt >= refreshNanos) {
      Map<String, ServiceMetrics> all = new HashMap<>();
      for (ServiceMetrics service : metrics.services()) {
        all.put(service.name(), service);
      }
      latest = all;
      takenAt = now;
      taken = true;
      generation++;
    }
    return latest.get(name);
  }

  /** {@return how many snapshots were taken so far: a new one may show nodes newly metered} */
  long generation() {
    return generation;
  }

  /**
   * Meters of {@code names} were just bound: if the snapshot lacks one of them (declared after
   * it was taken), the next read takes a new one.
   */
  synchronized void cover(Collection<String> names) {
    if (taken && !latest.keySet().containsAll(names)) {
      taken = false;
    }
  }
}

package dev.prime.faults;

import java.time.Duration;
import java.util.BitSet;
import java.util.HashMap;
import java.util.Map;
import java.util.OptionalLong;
import java.util.concurrent.TimeUnit;

/**
 * Counts what became of the ids {@code first .. first + count - 1} sent through a topology: how
 * many arrived, were lost, arrived twice, or arrived after a higher id (reordered). Each arrival
 * may carry a tag (the generation of the worker that processed it), so a test can tell when the
 * first value of a successor arrived and how often the processing host changed.
 *
 * <p>Design note: arrivals come from service threads, the test thread waits; every method
 * synchronises on the ledger, and {@link #awaitDistinct} waits on it with a deadline (no polling).
 */
final class Ledger {
  private final long first;
  private final int count;
  private final BitSet seen = new BitSet();
  private final BitSet refused = new BitSet();
  private final Map<Integer, Long> firstArrivalOfTag = new HashMap<>();
  private int arrivals;
  private int distinct;
  private int duplicated;
  private int reordered;
  private int unexpected;
  private int tagSwitches;
  private long highest = Long.MIN_VALUE;
  private Integer lastTag;

  Ledger(long first, int count) {
    this.first = first;
    this.count = count;
  }

  /** Records the arrival of {@code id}, processed by {@code tag}. */
  synchronized void arrived(long id, int tag) {
    arrivals++;
    firstArrivalOfTag.putIfAbsent(tag, System.nanoTime());
    if (lastTag != null && lastTag != tag) tagSwitches++;
    lastTag = tag;
    if (id < first || id >= first + count) {
      unexpected++;
      notifyAll();
      return;
    }
    int index = (int) (id - first);
    if (seen.get(index)) {
      duplicated++;
    } else {
      seen.set(index);
      distinct++;
      if (id < highest) reordered++;
      highest = Math.max(highest, id);
    }
    notifyAll();
  }

  /** Records that publishing {@code id} failed with an exception: it was never accepted. */
  synchronized void refused(long id) {
    refused.set((int) (id - first));
    notifyAll();
  }

  /** Waits until {@code n} distinct ids arrived; false if {@code timeout} passed first. */
  synchronized boolean awaitDistinct(int n, Duration timeout) throws InterruptedException {
    long deadline = System.nanoTime() + timeout.toNanos();
    while (distinct < n) {
      long left = deadline - System.nanoTime();
      if (left <= 0) return false;
      TimeUnit.NANOSECONDS.timedWait(this, left);
    }
    return true;
  }

  /** Waits until every accepted id arrived; false if {@code timeout} passed first. */
  synchronized boolean awaitAll(Duration timeout) throws InterruptedException {
    long deadline = System.nanoTime() + timeout.toNanos();
    while (lost() > 0) {
      long left = deadline - System.nanoTime();
      if (left <= 0) return false;
      TimeUnit.NANOSECONDS.timedWait(this, left);
    }
    return true;
  }

  /** Accepted ids that never arrived. */
  synchronized int lost() {
    BitSet missing = new BitSet();
    missing.set(0, count);
    missing.andNot(seen);
    missing.andNot(refused);
    return missing.cardinality();
  }

  synchronized int duplicated() {
    return duplicated;
  }

  synchronized int reordered() {
    return reordered;
  }

  synchronized int distinct() {
    return distinct;
  }

  /** Arrivals of ids outside the expected range. */
  synchronized int unexpected() {
    return unexpected;
  }

  /** Ids whose publish failed (not accepted). */
  synchronized int refusedCount() {
    return refused.cardinality();
  }

  /** How often consecutive arrivals came from different tags. */
  synchronized int tagSwitches() {
    return tagSwitches;
  }

  /** When (a {@link System#nanoTime()}) the first value processed by {@code tag} arrived. */
  synchronized OptionalLong firstArrivalOf(int tag) {
    Long at = firstArrivalOfTag.get(tag);
    return at == null ? OptionalLong.empty() : OptionalLong.of(at);
  }

  /** {@code 2000 sent, 0 lost, 0 duplicated, 0 reordered}. */
  synchronized String counts() {
    String line = count + " sent, " + lost() + " lost, " + duplicated + " duplicated, " + reordered + " reordered";
    if (refused.cardinality() > 0) line += ", " + refused.cardinality() + " refused at publish";
    if (unexpected > 0) line += ", " + unexpected + " unexpected";
    return line;
  }
}

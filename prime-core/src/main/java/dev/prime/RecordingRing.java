package dev.prime;

import java.time.Instant;
import java.util.ArrayList;
import java.util.List;
import java.util.function.BooleanSupplier;
import java.util.function.Predicate;

/**
 * The values recorded under one name: a ring of the latest {@code capacity} entries.
 *
 * <p>Design note (concurrency): one monitor per ring. {@link #record} is called by whichever
 * thread published or ran the chain (a service thread, a caller of {@code toBlock()}, a coroutine
 * on Optimus); it stamps and stores the value under the monitor, so sequence numbers and both
 * time stamps grow together, and it notifies only when a reader waits in {@link #awaitLatest}.
 * A source's values are stamped when the publish begins and stored once the media accepted them
 * (the three-argument {@code record}), so their stamps follow the sequence numbers of each
 * publishing thread, not across threads publishing to one event block at once.
 * Readers copy what they return under the same monitor. Slots are allocated as the ring fills, so
 * a name that records little costs little. A ring made by {@link #frozen} (a merged recording)
 * is never recorded into. Subscribed listeners ({@link Recording#subscribe}) are called inside
 * the monitor after each store, so each name's values reach them in sequence order; they must not
 * block (their contract says so).
 */
final class RecordingRing {
  private final String service;
  private final String pseudoname;
  private final int capacity;
  private final ArrayList<RecordedValue<Object>> slots;
  private long written; // entries ever stored; the next live value's sequence number
  private long dropped;
  private int waiters;
  private final List<Recording.Subscription> subscriptions; // called after each store

  RecordingRing(String service, String pseudoname, int capacity) {
    this(service, pseudoname, capacity, List.of());
  }

  RecordingRing(
      String service,
      String pseudoname,
      int capacity,
      List<Recording.Subscription> subscriptions) {
    this.subscriptions = subscriptions;
    this.service = service;
    this.pseudoname = pseudoname;
    this.capacity = capacity;
    this.slots = new ArrayList<>(Math.min(capacity, 16));
  }

  /** A ring holding {@code entries} in their order, with {@code dropped} counted before them. */
  static RecordingRing frozen(
      String service, String pseudoname, List<RecordedValue<Object>> entries, long dropped) {
    RecordingRing ring = new RecordingRing(service, pseudoname, Math.max(1, entries.size()));
    ring.slots.addAll(entries);
    ring.written = entries.size();
    ring.dropped = dropped;
    return ring;
  }

  String service() {
    return service;
  }

  String pseudoname() {
    return pseudoname;
  }

  /** Stamps and stores a value; the oldest falls out (counted) when the ring is full. */
  synchronized void record(Object value) {
    record(value, Instant.now(), System.nanoTime());
  }

  /** Stores a value stamped before it was handed on (a source's publish); see {@link #record}. */
  synchronized void record(Object value, Instant wallTime, long monotonicNanos) {
    RecordedValue<Object> entry =
        new RecordedValue<>(service, pseudoname, written, wallTime, monotonicNanos, value);
    if (slots.size() < capacity) {
      slots.add(entry);
    } else {
      slots.set((int) (written % capacity), entry);
      dropped++;
    }
    written++;
    if (waiters > 0) {
      notifyAll();
    }
    if (!subscriptions.isEmpty()) {
      for (Recording.Subscription subscription : subscriptions) {
        subscription.deliver(entry);
      }
    }
  }

  /** The latest entry, or {@code null}. */
  synchronized RecordedValue<Object> latest() {
    return slots.isEmpty() ? null : slots.get((int) ((written - 1) % capacity));
  }

  /**
   * The latest entry, waiting up to {@code timeoutNanos} for a first one while {@code stopped}
   * says no (checked at least every 100 ms: a closed core records nothing more); {@code null} if
   * none came.
   */
  synchronized RecordedValue<Object> awaitLatest(long timeoutNanos, BooleanSupplier stopped)
      throws InterruptedException {
    long deadline = System.nanoTime() + timeoutNanos;
    waiters++;
    try {
      while (slots.isEmpty()) {
        long left = deadline - System.nanoTime();
        if (left <= 0 || stopped.getAsBoolean()) {
          return null;
        }
        wait(Math.max(1, Math.min(100, left / 1_000_000)), 0);
      }
      return latest();
    } finally {
      waiters--;
    }
  }

  /** The retained entries that pass {@code keep}, oldest first. */
  synchronized List<RecordedValue<Object>> entries(Predicate<RecordedValue<Object>> keep) {
    List<RecordedValue<Object>> out = new ArrayList<>();
    int size = slots.size();
    int oldest = size < capacity ? 0 : (int) (written % capacity);
    for (int i = 0; i < size; i++) {
      RecordedValue<Object> entry = slots.get((oldest + i) % size);
      if (keep.test(entry)) {
        out.add(entry);
      }
    }
    return out;
  }

  /** {@return how many values fell out of the ring} */
  synchronized long dropped() {
    return dropped;
  }

  /** {@return how many values were recorded, retained or dropped} */
  synchronized long recorded() {
    return slots.size() + dropped;
  }
}

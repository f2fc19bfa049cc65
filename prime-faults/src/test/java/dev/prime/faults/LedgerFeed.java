package dev.prime.faults;

import dev.prime.CoreClosedException;
import dev.prime.Reader;
import java.time.Duration;
import java.util.Optional;
import java.util.concurrent.atomic.AtomicReference;
import java.util.concurrent.locks.LockSupport;

/**
 * Hands every value a reader receives to the current {@link Ledger} (a stamped value carries its
 * id and the generation of the process that ran it), on a daemon thread.
 *
 * <p>Design note: the thread takes with a short timeout so that it sees {@link #close()}; a read
 * that fails while Redis is unreachable is counted and retried after a pause; the thread ends when
 * the feed or the core is closed, and in any case after {@link #MAX_LIFE}.
 */
final class LedgerFeed implements AutoCloseable {
  private static final Duration POLL = Duration.ofMillis(200);
  private static final Duration MAX_LIFE = Duration.ofMinutes(30);

  private final Thread thread;
  private volatile boolean closed;

  private LedgerFeed(Reader<Long> reader, AtomicReference<Ledger> sink, String name) {
    thread = new Thread(() -> feed(reader, sink), "fault-ledger-feed-" + name);
    thread.setDaemon(true);
    thread.start();
  }

  /** Starts feeding {@code sink}'s ledger from {@code reader} (call after the core's {@code start()}). */
  static LedgerFeed start(Reader<Long> reader, AtomicReference<Ledger> sink, String name) {
    return new LedgerFeed(reader, sink, name);
  }

  @Override
  public void close() {
    closed = true;
    try {
      thread.join(FaultMode.PATIENCE.toMillis());
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
    }
  }

  private void feed(Reader<Long> reader, AtomicReference<Ledger> sink) {
    long end = System.nanoTime() + MAX_LIFE.toNanos();
    while (!closed && System.nanoTime() < end) {
      try {
        Optional<Long> value = reader.take(POLL);
        if (value.isPresent()) {
          long stamped = value.get();
          Ledger ledger = sink.get();
          if (ledger != null) ledger.arrived(stamped % StreamTopology.GENERATION, (int) (stamped / StreamTopology.GENERATION));
        }
      } catch (CoreClosedException | IllegalStateException e) {
        return; // the core or the reader is closed
      } catch (InterruptedException e) {
        return;
      } catch (RuntimeException e) {
        LockSupport.parkNanos(POLL.toNanos()); // Redis unreachable: try again shortly
      }
    }
  }
}

package dev.prime.faults;

import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.EventBlock;
import java.time.Duration;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicReference;

/**
 * One kill-mid-stream run of the stream topology: this process publishes ids and reads the output
 * (a {@link LedgerFeed} counts it), worker JVMs host {@code stamp}. The publisher sends the first part,
 * waits until the victim worker has been stopped, and sends the rest; a successor worker of the
 * next generation is started, and the ledger counts what arrived.
 */
final class StreamRun {
  private final String url;
  private final String coreName;
  private final int retention;
  private final EventBlock<Long> ids;
  private final AtomicReference<Ledger> sink;

  StreamRun(String url, String coreName, int retention, EventBlock<Long> ids, AtomicReference<Ledger> sink) {
    this.url = url;
    this.coreName = coreName;
    this.retention = retention;
    this.ids = ids;
    this.sink = sink;
  }

  /** Starts a worker of {@code generation} hosting {@code stamp} and waits for its READY line. */
  WorkerJvm startWorker(int generation) throws InterruptedException {
    WorkerJvm worker = WorkerJvm.start(coreName + "-gen" + generation,
        "stream", url, coreName, Integer.toString(retention), Integer.toString(generation));
    try {
      worker.awaitReady();
    } catch (AssertionError | InterruptedException e) {
      worker.close();
      throw e;
    }
    return worker;
  }

  /** What a run measured; {@code successor} is the running worker afterwards. */
  record Outcome(Ledger ledger, WorkerJvm successor, long recoveredNanos, long killedAt) {}

  /**
   * Sends ids {@code first .. first + n - 1}; once {@code killAfter} of them arrived (the publisher
   * pauses after {@code pauseAfter}), stops {@code victim} with SIGKILL ({@code forcibly}) or
   * SIGTERM, and starts a successor of {@code generation}: at once, or, with {@code backlogFirst},
   * only after the rest was published to the service while nobody hosted it.
   */
  Outcome killMidStream(WorkerJvm victim, boolean forcibly, int generation, long first, int n,
      int pauseAfter, int killAfter, boolean backlogFirst) throws Exception {
    Ledger ledger = new Ledger(first, n);
    sink.set(ledger);
    CountDownLatch killed = new CountDownLatch(1);
    Thread publisher = publisher(ids, ledger, first, n, pauseAfter, killed);
    try {
      assertTrue(ledger.awaitDistinct(killAfter, FaultMode.PATIENCE),
          "only " + ledger.distinct() + " of " + killAfter + " ids arrived before the kill; worker output:\n" + victim.output());
      if (forcibly) victim.kill(); else victim.terminate();
      long killedAt = System.nanoTime();
      killed.countDown();
      if (backlogFirst) {
        publisher.join(FaultMode.PATIENCE.toMillis());
        assertFalse(publisher.isAlive(), "the publisher did not finish");
      }
      WorkerJvm successor = startWorker(generation);
      boolean all = ledger.awaitAll(FaultMode.PATIENCE);
      // anything arriving twice comes right behind the rest: give it a moment to show
      Bounded.hold(Duration.ofMillis(300));
      long recovered = ledger.firstArrivalOf(generation).orElse(Long.MAX_VALUE);
      if (!all) {
        System.out.println(coreName + ": not every id arrived (" + ledger.counts() + "); successor output:\n" + successor.output());
      }
      return new Outcome(ledger, successor, recovered == Long.MAX_VALUE ? -1 : recovered - killedAt, killedAt);
    } finally {
      killed.countDown();
      publisher.join(FaultMode.PATIENCE.toMillis());
    }
  }

  /** Publishes ids {@code first..first+n-1}, pausing after {@code pauseAfter} until {@code resume}. */
  static Thread publisher(EventBlock<Long> ids, Ledger ledger, long first, int n, int pauseAfter, CountDownLatch resume) {
    Thread thread = new Thread(() -> {
      try {
        for (int i = 0; i < n; i++) {
          if (i == pauseAfter && !resume.await(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS)) return;
          try {
            ids.publish(first + i);
          } catch (RuntimeException e) {
            ledger.refused(first + i);
          }
        }
      } catch (InterruptedException e) {
        Thread.currentThread().interrupt();
      }
    }, "fault-publisher");
    thread.start();
    return thread;
  }
}

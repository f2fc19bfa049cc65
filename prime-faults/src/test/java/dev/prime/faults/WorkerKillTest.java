package dev.prime.faults;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.EventBlock;
import dev.prime.optimus.OptimusCore;
import java.util.concurrent.atomic.AtomicReference;
import org.junit.jupiter.api.Test;

/**
 * Classic fault: the worker JVM hosting {@code stamp} is killed mid-stream, with SIGKILL (a crash)
 * and with SIGTERM (a graceful stop), and a successor takes over. Nothing accepted is lost,
 * duplicated or reordered. Short mode: 2 runs x 2,000 ids per signal; long: 6 x 10,000.
 */
class WorkerKillTest {

  @Test
  void sigkillMidStreamLosesDuplicatesAndReordersNothing() throws Exception {
    killRuns("SIGKILL", true);
  }

  @Test
  void sigtermMidStreamLosesDuplicatesAndReordersNothing() throws Exception {
    killRuns("SIGTERM", false);
  }

  private void killRuns(String signal, boolean forcibly) throws Exception {
    FaultMode mode = FaultMode.current();
    String coreName = "kill-" + signal.toLowerCase(java.util.Locale.ROOT);
    int n = mode.idsPerRun;
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null)) {
      AtomicReference<Ledger> sink = new AtomicReference<>();
      EventBlock<Long> ids = new EventBlock<>();
      try (OptimusCore core = Cores.core(redis.url(), coreName, StreamTopology.WIDE_RETENTION)) {
        var stream = StreamTopology.declareStream(core, ids, 0, true);
        core.start();
        LedgerFeed.start(stream.observer(), sink, coreName);
        StreamRun runs = new StreamRun(redis.url(), coreName, StreamTopology.WIDE_RETENTION, ids, sink);
        WorkerJvm worker = runs.startWorker(1);
        try {
          for (int run = 1; run <= mode.killRuns; run++) {
            StreamRun.Outcome outcome = runs.killMidStream(worker, forcibly, run + 1, (long) (run - 1) * n, n, 2 * n / 5, n / 3, false);
            worker = outcome.successor();
            Ledger ledger = outcome.ledger();
            Figures.report("kill-worker " + signal + " run " + run + "/" + mode.killRuns + ": " + ledger.counts()
                + ", recovered in " + Figures.seconds(outcome.recoveredNanos()));
            assertEquals(0, ledger.lost(), "lost: " + ledger.counts() + "\n" + worker.output());
            assertEquals(0, ledger.duplicated(), "duplicated: " + ledger.counts());
            assertEquals(0, ledger.reordered(), "reordered: " + ledger.counts());
            assertEquals(0, ledger.refusedCount(), "refused: " + ledger.counts());
            assertTrue(outcome.recoveredNanos() >= 0, "the successor delivered no value: " + ledger.counts() + "\n" + worker.output());
          }
        } finally {
          worker.close();
        }
      }
    }
  }
}

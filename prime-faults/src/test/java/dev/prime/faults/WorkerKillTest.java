package dev.prime.faults;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.EventBlock;
import dev.prime.optimus.OptimusCore;
import java.util.concurrent.atomic.AtomicReference;
import org.junit.jupiter.params.ParameterizedTest;
import org.junit.jupiter.params.provider.EnumSource;

/**
 * Classic fault: the worker JVM hosting {@code stamp} is killed mid-stream, with SIGKILL (a crash)
 * and with SIGTERM (a graceful stop), and a successor takes over. Nothing accepted is lost,
 * duplicated or reordered: on one redis-server reached directly, on one reached over a slow
 * network (every answer comes at least a millisecond late), and on a real Redis Cluster of 3
 * masters and 3 replicas (see {@link RedisSetup}). Short mode: 2 runs x 2,000 ids per signal and Redis;
 * long: 6 x 10,000.
 */
class WorkerKillTest {

  @ParameterizedTest(name = "{0}")
  @EnumSource(RedisSetup.class)
  void sigkillMidStreamLosesDuplicatesAndReordersNothing(RedisSetup setup) throws Exception {
    try (RedisSetup.Redis redis = setup.start()) {
      killRuns("SIGKILL", true, redis.url(), setup.suffix());
    }
  }

  @ParameterizedTest(name = "{0}")
  @EnumSource(RedisSetup.class)
  void sigtermMidStreamLosesDuplicatesAndReordersNothing(RedisSetup setup) throws Exception {
    try (RedisSetup.Redis redis = setup.start()) {
      killRuns("SIGTERM", false, redis.url(), setup.suffix());
    }
  }

  private void killRuns(String signal, boolean forcibly, String url, String where) throws Exception {
    FaultMode mode = FaultMode.current();
    String coreName = "kill-" + signal.toLowerCase(java.util.Locale.ROOT);
    String run = "kill-worker " + signal + where;
    int n = mode.idsPerRun;
    AtomicReference<Ledger> sink = new AtomicReference<>();
    EventBlock<Long> ids = new EventBlock<>();
    try (OptimusCore core = Cores.core(url, coreName, StreamTopology.WIDE_RETENTION)) {
      var stream = StreamTopology.declareStream(core, ids, 0, true);
      core.start();
      LedgerFeed.start(stream.observer(), sink, coreName);
      StreamRun runs = new StreamRun(url, coreName, StreamTopology.WIDE_RETENTION, ids, sink);
      WorkerJvm worker = runs.startWorker(1);
      try {
        for (int i = 1; i <= mode.killRuns; i++) {
          StreamRun.Outcome outcome = runs.killMidStream(worker, forcibly, i + 1, (long) (i - 1) * n, n, 2 * n / 5, n / 3, false);
          worker = outcome.successor();
          Ledger ledger = outcome.ledger();
          Figures.report(run + " run " + i + "/" + mode.killRuns + ": " + ledger.counts()
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

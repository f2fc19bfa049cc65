package dev.prime.faults;

import static org.junit.jupiter.api.Assertions.assertEquals;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.optimus.OptimusCore;
import java.util.concurrent.atomic.AtomicReference;
import org.junit.jupiter.params.ParameterizedTest;
import org.junit.jupiter.params.provider.EnumSource;

/**
 * Issue 9 item 1: the worker JVM hosting a service is killed and, while it is down, far more
 * values than the source retention (the default 1024) are published; a successor processes every
 * one of them. A service's input is a queue, not a retention window. On every {@link RedisSetup}.
 */
class RetentionTest {

  @ParameterizedTest(name = "{0}")
  @EnumSource(RedisSetup.class)
  void valuesPublishedWhileTheHostIsDownAreNotTrimmedAway(RedisSetup setup) throws Exception {
    int retention = CoreConfig.defaults().sourceRetention();
    int backlog = FaultMode.current().backlog;
    int first = 500;
    int n = first + backlog;
    String name = "retention";
    AtomicReference<Ledger> sink = new AtomicReference<>();
    EventBlock<Long> ids = new EventBlock<>();
    try (RedisSetup.Redis redis = setup.start();
        OptimusCore core = Cores.core(redis.url(), name, retention)) {
      var stream = StreamTopology.declareStream(core, ids, 0, true);
      core.start();
      LedgerFeed.start(stream.observer(), sink, name);
      // the workers publish stamp's output with a wide retention: only the service input is at stake
      StreamRun runs = new StreamRun(redis.url(), name, StreamTopology.WIDE_RETENTION, ids, sink);
      WorkerJvm host = runs.startWorker(1);
      try {
        StreamRun.Outcome outcome = runs.killMidStream(host, true, 2, 0, n, first, first, true);
        host = outcome.successor();
        Ledger ledger = outcome.ledger();
        Figures.report("host down" + setup.suffix() + ", " + backlog + " published (retention " + retention + "): " + ledger.counts()
            + ", successor's first value " + Figures.seconds(outcome.recoveredNanos()) + " after the kill");
        assertEquals(0, ledger.lost(), "nothing accepted is lost: " + ledger.counts());
        assertEquals(0, ledger.duplicated(), ledger.counts());
        assertEquals(0, ledger.reordered(), ledger.counts());
        assertEquals(0, ledger.refusedCount(), ledger.counts());
      } finally {
        host.close();
      }
    }
  }
}

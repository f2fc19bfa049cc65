package dev.prime.faults;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.EventBlock;
import dev.prime.optimus.OptimusCore;
import java.nio.file.Path;
import java.time.Duration;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.atomic.AtomicReference;
import org.junit.jupiter.api.io.TempDir;
import org.junit.jupiter.params.ParameterizedTest;
import org.junit.jupiter.params.provider.EnumSource;

/**
 * redis-server crashes (SIGKILL; in the long mode every second run a SIGTERM) mid-stream and comes
 * back on the same port: with its append-only file ({@code appendfsync always}) nothing accepted
 * is lost and values flow again within seconds (classic); empty (no persistence), every process
 * re-declares its part of the topology, counts the reset, and values published after Redis is
 * back arrive (issue 9 item 2). Both on a direct network and on a slow one (every answer from Redis
 * comes at least a millisecond late, see {@link RedisSetup}).
 */
class RedisRestartFaultTest {
  /** How soon after a restart values must flow again. */
  private static final Duration FLOW_BACK = Duration.ofSeconds(10);

  @ParameterizedTest(name = "{0}")
  @EnumSource(value = RedisSetup.class, names = {"DIRECT", "SLOW_NETWORK"})
  void crashWithAppendOnlyFileLosesNothingAndFlowsBack(RedisSetup setup, @TempDir Path dir) throws Exception {
    FaultMode mode = FaultMode.current();
    int n = mode.idsPerRun;
    AtomicReference<Ledger> sink = new AtomicReference<>();
    EventBlock<Long> ids = new EventBlock<>();
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.AOF_ALWAYS, dir);
        RedisSetup.Redis way = setup.through(redis);
        OptimusCore core = Cores.core(way.url(), "redis-aof", StreamTopology.WIDE_RETENTION, "stamp")) {
      var stream = StreamTopology.declareStream(core, ids, 0, true);
      core.start();
      LedgerFeed.start(stream.observer(), sink, "redis-aof");
      for (int run = 1; run <= mode.redisRuns; run++) {
        long first = (long) (run - 1) * n;
        Ledger ledger = new Ledger(first, n);
        sink.set(ledger);
        CountDownLatch restarted = new CountDownLatch(1);
        Thread publisher = StreamRun.publisher(ids, ledger, first, n, 2 * n / 5, restarted);
        long flowBack;
        try {
          assertTrue(ledger.awaitDistinct(n / 3, FaultMode.PATIENCE), "before the crash: " + ledger.counts());
          // a crash; in the long mode every second run stops it with SIGTERM instead
          if (run % 2 == 0) redis.terminate(); else redis.kill();
          Bounded.hold(mode.redisOutage);
          redis.restart(true);
          long restartedAt = System.nanoTime();
          int before = ledger.distinct();
          restarted.countDown();
          flowBack = ledger.awaitDistinct(before + 1, FaultMode.PATIENCE) ? System.nanoTime() - restartedAt : -1;
          ledger.awaitAll(FaultMode.PATIENCE);
          Bounded.hold(Duration.ofMillis(300)); // duplicates would come right behind
        } finally {
          restarted.countDown();
          publisher.join(FaultMode.PATIENCE.toMillis());
        }
        Figures.report("redis-" + (run % 2 == 0 ? "SIGTERM" : "SIGKILL") + " (AOF always)" + setup.suffix() + " run " + run + "/" + mode.redisRuns + ", down "
            + Figures.seconds(mode.redisOutage) + ": " + ledger.counts() + ", flow back "
            + (flowBack < 0 ? "never" : "in " + Figures.seconds(flowBack)) + " after the restart");
        assertEquals(0, ledger.lost(), ledger.counts());
        assertEquals(0, ledger.duplicated(), ledger.counts());
        assertEquals(0, ledger.reordered(), ledger.counts());
        assertTrue(flowBack >= 0 && flowBack < FLOW_BACK.toNanos(), "values flow again within " + FLOW_BACK);
      }
    }
  }

  @ParameterizedTest(name = "{0}")
  @EnumSource(value = RedisSetup.class, names = {"DIRECT", "SLOW_NETWORK"})
  void restartWithoutDataIsCountedAndValuesPublishedAfterItArrive(RedisSetup setup) throws Exception {
    int before = 100;
    int after = FaultMode.current().idsPerRun / 4;
    AtomicReference<Ledger> sink = new AtomicReference<>();
    EventBlock<Long> ids = new EventBlock<>();
    String name = "redis-empty";
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null);
        RedisSetup.Redis way = setup.through(redis);
        OptimusCore worker = Cores.core(way.url(), name, StreamTopology.WIDE_RETENTION, "stamp");
        OptimusCore collector = Cores.core(way.url(), name, StreamTopology.WIDE_RETENTION)) {
      StreamTopology.declareStream(worker, new EventBlock<>(), 1, false);
      var stream = StreamTopology.declareStream(collector, ids, 0, true);
      worker.start();
      collector.start();
      LedgerFeed.start(stream.observer(), sink, name);
      Ledger warmUp = new Ledger(0, before);
      sink.set(warmUp);
      for (long id = 0; id < before; id++) ids.publish(id);
      assertTrue(warmUp.awaitAll(FaultMode.PATIENCE), "before the restart: " + warmUp.counts());

      redis.kill();
      redis.restart(false);
      long restartedAt = System.nanoTime();
      // each live process re-declares what it hosts and reads within about one heartbeat
      long redeclared = Bounded.await(Duration.ofSeconds(30), () -> worker.redisResets() >= 1 && collector.redisResets() >= 1);

      Ledger ledger = new Ledger(before, after);
      sink.set(ledger);
      for (long id = before; id < before + after; id++) {
        try {
          ids.publish(id);
        } catch (RuntimeException e) {
          ledger.refused(id);
        }
      }
      ledger.awaitAll(Duration.ofSeconds(20));
      Bounded.hold(Duration.ofMillis(300));
      long workerResets = worker.redisResets();
      long collectorResets = collector.redisResets();
      Figures.report("redis-restart empty" + setup.suffix() + ": " + ledger.counts() + " (published after it was back), redisResets() "
          + workerResets + " in the worker, " + collectorResets + " in the collector, re-declared "
          + (redeclared < 0 ? "(not seen)" : "in " + Figures.seconds(redeclared)) + " after the restart ("
          + Figures.seconds(System.nanoTime() - restartedAt) + " to the end of the run)");
      assertEquals(0, ledger.lost(), "values published after Redis came back empty must arrive: " + ledger.counts());
      assertEquals(0, ledger.duplicated(), ledger.counts());
      assertEquals(0, ledger.reordered(), ledger.counts());
      assertEquals(0, ledger.refusedCount(), ledger.counts());
      assertTrue(workerResets >= 1 && collectorResets >= 1, "both processes count the reset: " + workerResets + ", " + collectorResets);
    }
  }
}

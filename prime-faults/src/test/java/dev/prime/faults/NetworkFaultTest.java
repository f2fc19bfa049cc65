package dev.prime.faults;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.EventBlock;
import dev.prime.optimus.OptimusCore;
import java.time.Duration;
import java.util.List;
import java.util.Map;
import java.util.concurrent.ConcurrentHashMap;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.atomic.AtomicInteger;
import java.util.concurrent.atomic.AtomicReference;
import org.junit.jupiter.api.Test;

/**
 * The network between a process and Redis fails, through the suite's {@link FaultProxy}: frozen in
 * both directions for longer than the blocking-socket timeout (classic: noticed, nothing lost),
 * every connection of a slow (1 ms) network cut three times mid-stream (classic: nothing lost), and
 * a connection cut right after a call's request reached Redis (issue 9 item 3: every call returns,
 * and the service runs each call once).
 */
class NetworkFaultTest {
  /** Longer than the 6 s a blocked read waits on a silent socket; shorter than the 10 s a publish may wait. */
  private static final Duration FREEZE = Duration.ofSeconds(8);

  @Test
  void frozenConnectionsAreNoticedAndNothingIsLost() throws Exception {
    int n = FaultMode.current().idsPerRun;
    AtomicReference<Ledger> sink = new AtomicReference<>();
    EventBlock<Long> ids = new EventBlock<>();
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null);
        FaultProxy proxy = new FaultProxy(redis.port());
        OptimusCore core = Cores.core(proxy.url(), "frozen", StreamTopology.WIDE_RETENTION, "stamp")) {
      var stream = StreamTopology.declareStream(core, ids, 0, true);
      core.start();
      LedgerFeed.start(stream.observer(), sink, "frozen");
      Ledger ledger = new Ledger(0, n);
      sink.set(ledger);
      CountDownLatch frozen = new CountDownLatch(1);
      Thread publisher = StreamRun.publisher(ids, ledger, 0, n, 2 * n / 5, frozen);
      long noticed;
      long flowBack;
      try {
        // everything sent so far has arrived: the services wait in blocking reads when the network freezes
        assertTrue(ledger.awaitDistinct(2 * n / 5, FaultMode.PATIENCE), "before the freeze: " + ledger.counts());
        proxy.freeze();
        long frozenAt = System.nanoTime();
        frozen.countDown(); // the rest is published into the frozen network
        noticed = proxy.awaitClientNoticedFreeze(FREEZE);
        Bounded.hold(FREEZE.minusNanos(System.nanoTime() - frozenAt));
        int before = ledger.distinct();
        proxy.thaw();
        long thawedAt = System.nanoTime();
        flowBack = ledger.awaitDistinct(before + 1, FaultMode.PATIENCE) ? System.nanoTime() - thawedAt : -1;
        ledger.awaitAll(FaultMode.PATIENCE);
        Bounded.hold(Duration.ofMillis(300));
      } finally {
        frozen.countDown();
        publisher.join(FaultMode.PATIENCE.toMillis());
      }
      Figures.report("freeze " + Figures.seconds(FREEZE) + ": " + ledger.counts() + ", noticed "
          + (noticed < 0 ? "never" : "in " + Figures.seconds(noticed)) + ", flow back "
          + (flowBack < 0 ? "never" : "in " + Figures.seconds(flowBack)) + " after the thaw, "
          + proxy.acceptedConnections() + " connections made through the proxy");
      assertTrue(noticed >= 0, "no client gave up on a frozen connection within " + FREEZE);
      assertEquals(0, ledger.lost(), ledger.counts());
      assertEquals(0, ledger.duplicated(), ledger.counts());
      assertEquals(0, ledger.reordered(), ledger.counts());
      assertEquals(0, ledger.refusedCount(), ledger.counts());
    }
  }

  @Test
  void connectionsCutMidStreamOnASlowNetworkLoseNothing() throws Exception {
    int n = FaultMode.current().idsPerRun / 4;
    int cuts = 3;
    AtomicReference<Ledger> sink = new AtomicReference<>();
    EventBlock<Long> ids = new EventBlock<>();
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null);
        FaultProxy proxy = new FaultProxy(redis.port());
        OptimusCore core = Cores.core(proxy.url(), "cut-all", StreamTopology.WIDE_RETENTION, "stamp")) {
      proxy.delay(Duration.ofMillis(1));
      var stream = StreamTopology.declareStream(core, ids, 0, true);
      core.start();
      LedgerFeed.start(stream.observer(), sink, "cut-all");
      Ledger ledger = new Ledger(0, n);
      sink.set(ledger);
      CountDownLatch go = new CountDownLatch(1);
      Thread publisher = StreamRun.publisher(ids, ledger, 0, n, 0, go);
      go.countDown();
      List<Integer> cut = new java.util.ArrayList<>();
      try {
        for (int k = 1; k <= cuts; k++) {
          assertTrue(ledger.awaitDistinct(k * n / (cuts + 1), FaultMode.PATIENCE), "before cut " + k + ": " + ledger.counts());
          cut.add(proxy.cutAll());
        }
        ledger.awaitAll(FaultMode.PATIENCE);
        Bounded.hold(Duration.ofMillis(300));
      } finally {
        publisher.join(FaultMode.PATIENCE.toMillis());
      }
      Figures.report("cut all connections " + cuts + " times mid-stream (" + cut + " connections) on a 1 ms network: "
          + ledger.counts() + ", " + proxy.acceptedConnections() + " connections made through the proxy");
      assertEquals(0, ledger.lost(), ledger.counts());
      assertEquals(0, ledger.duplicated(), ledger.counts());
      assertEquals(0, ledger.reordered(), ledger.counts());
      assertEquals(0, ledger.refusedCount(), ledger.counts());
      assertTrue(cut.stream().allMatch(c -> c > 0), "every cut closed connections: " + cut);
    }
  }

  @Test
  void everyCallReturnsOnceWhenItsConnectionIsCutAfterTheRequest() throws Exception {
    int calls = FaultMode.current().cutCalls;
    String name = "cut-call";
    Map<Long, AtomicInteger> runs = new ConcurrentHashMap<>();
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null);
        FaultProxy proxy = new FaultProxy(redis.port());
        OptimusCore host = Cores.core(redis.url(), name, 1024, "echo");
        OptimusCore caller = Cores.builder(proxy.url(), name, 1024, null)
            .callTimeout(Duration.ofSeconds(3)).hosts(List.of()).build()) {
      host.<Long, Long>chain("echo", x -> {
        runs.computeIfAbsent(x, k -> new AtomicInteger()).incrementAndGet();
        return x;
      }).toBlock(); // binds the service this core hosts
      Block<Long, Long> echo = caller.<Long, Long>chain("echo", x -> x).toBlock();
      host.start();
      caller.start();
      assertEquals(-1L, echo.process(-1L), "a call before any fault");

      byte[] request = TopologyKeys.bytes(new TopologyKeys(name).serviceInput("echo"));
      int returned = 0;
      int wrong = 0;
      long slowest = 0;
      StringBuilder failures = new StringBuilder();
      for (long i = 0; i < calls; i++) {
        proxy.cutAfterNextClientWrite(request);
        long started = System.nanoTime();
        try {
          Long answer = echo.process(i);
          returned++;
          if (answer == null || answer != i) wrong++;
        } catch (RuntimeException e) {
          failures.append("\n  call ").append(i).append(": ").append(e);
        }
        slowest = Math.max(slowest, System.nanoTime() - started);
      }
      int cuts = proxy.cutsDone();
      long ranOnce = runs.entrySet().stream().filter(e -> e.getKey() >= 0 && e.getValue().get() == 1).count();
      long ranTwice = runs.entrySet().stream().filter(e -> e.getKey() >= 0 && e.getValue().get() > 1).count();
      Figures.report("cut-after-request: " + calls + " calls, " + cuts + " connections cut after the request, "
          + returned + " returned, " + (calls - returned) + " failed, " + wrong + " wrong answers, service ran "
          + ranOnce + " once and " + ranTwice + " more than once, slowest call " + Figures.seconds(slowest));
      assertEquals(calls, cuts, "every call's connection was cut right after its request");
      assertEquals(calls, returned, "every call returns:" + failures);
      assertEquals(0, wrong);
      assertEquals(calls, ranOnce, "the service ran every call exactly once: " + runs);
    }
  }
}

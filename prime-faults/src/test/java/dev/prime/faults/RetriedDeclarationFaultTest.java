package dev.prime.faults;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.CoreClosedException;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.optimus.OptimusCore;
import java.nio.file.Path;
import java.time.Duration;
import java.util.List;
import java.util.Set;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicReference;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;
import redis.clients.jedis.Jedis;

/**
 * A declaration made after {@code start()} that hosts a service here and fails (another process
 * holds the service's host lease) is taken back and can be made again, also when the process that
 * held the lease is killed with SIGKILL, when redis-server is killed and restarted while the failed
 * declaration is undone or while its retry is made, and when the network to Redis freezes while the
 * declaration waits: counted in values lost and duplicated, seconds to recover, threads,
 * connections and host leases left behind.
 */
class RetriedDeclarationFaultTest {
  /** How a one-key {@code HOST_RELEASE} script call starts on the wire: EVALSHA, its hash, 1, the key, the instance. */
  private static final String ONE_KEY_RELEASE = "*5\r\n$7\r\nEVALSHA\r\n";
  /** How a two-key {@code HOST_CLAIM} script call starts: EVALSHA, its hash, 2, two keys, the instance, the lease. */
  private static final String TWO_KEY_CLAIM = "*7\r\n$7\r\nEVALSHA\r\n";
  /** How a one-key {@code HOST_CLAIM} script call starts. */
  private static final String ONE_KEY_CLAIM = "*6\r\n$7\r\nEVALSHA\r\n";

  @Test
  void aRetryAfterAKilledHostsLeaseLapsedHostsTheServiceAndEveryValueArrivesOnce() throws Exception {
    int n = FaultMode.current().idsPerRun;
    String name = "retried-after-kill";
    TopologyKeys keys = new TopologyKeys(name);
    AtomicReference<Ledger> sink = new AtomicReference<>();
    EventBlock<Long> ids = new EventBlock<>();
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null);
        Jedis raw = redis.client();
        OptimusCore observer = Cores.core(redis.url(), name, StreamTopology.WIDE_RETENTION);
        OptimusCore declaring = Cores.builder(redis.url(), name, StreamTopology.WIDE_RETENTION, null).build()) {
      var stream = StreamTopology.declareStream(observer, ids, 0, true);
      Source<Long> declaredIds = declaring.source("ids", new EventBlock<Long>());
      Chain<Long, Long> stamp = declaring.chain("stamp", id -> 2 * StreamTopology.GENERATION + id);
      observer.start();
      declaring.start();
      LedgerFeed.start(stream.observer(), sink, name);
      StreamRun runs = new StreamRun(redis.url(), name, StreamTopology.WIDE_RETENTION, ids, sink);
      Ledger ledger = new Ledger(0, n);
      sink.set(ledger);
      CountDownLatch killed = new CountDownLatch(1);
      Thread publisher;
      String refusal;
      long refusedIn;
      long killedAt;
      long lapsedIn;
      long retriedIn;
      try (WorkerJvm host = runs.startWorker(1)) {
        publisher = StreamRun.publisher(ids, ledger, 0, n, 2 * n / 5, killed);
        assertTrue(ledger.awaitDistinct(n / 3, FaultMode.PATIENCE), "before the refusal: " + ledger.counts() + "\n" + host.output());
        long started = System.nanoTime();
        IllegalStateException refused = assertThrows(IllegalStateException.class, () -> declaredIds.then(stamp),
            "the worker holds the host lease of 'stamp'");
        refusedIn = System.nanoTime() - started;
        refusal = refused.getMessage();
        host.kill();
        killedAt = System.nanoTime();
      }
      Source<Long> hosted;
      try {
        killed.countDown(); // the rest is published while nobody hosts 'stamp'
        lapsedIn = Bounded.await(Duration.ofSeconds(20), () -> !raw.exists(keys.hostLease("stamp")));
        long retried = System.nanoTime();
        hosted = declaredIds.then(stamp);
        retriedIn = System.nanoTime() - retried;
        ledger.awaitAll(FaultMode.PATIENCE);
        Bounded.hold(Duration.ofMillis(300)); // duplicates would come right behind
      } finally {
        killed.countDown();
        publisher.join(FaultMode.PATIENCE.toMillis());
      }
      long recovered = ledger.firstArrivalOf(2).orElse(Long.MAX_VALUE);
      Figures.report("retried declaration after a SIGKILLed host: refused after " + Figures.seconds(refusedIn)
          + ", the killed host's lease lapsed " + (lapsedIn < 0 ? "never" : Figures.seconds(lapsedIn)) + " after the kill, the retry took "
          + Figures.seconds(retriedIn) + "; " + ledger.counts() + ", first value of the retried host "
          + (recovered == Long.MAX_VALUE ? "never" : Figures.seconds(recovered - killedAt)) + " after the kill, host switches "
          + ledger.tagSwitches());
      assertDeclarationRefused(refusal, "stamp");
      assertTrue(lapsedIn >= 0, "the killed worker's host lease of 'stamp' lapses");
      assertEquals(Set.of("stamp"), Set.copyOf(declaring.serviceNames()), "the retried declaration hosts 'stamp' here");
      assertTrue(hosted != null && recovered != Long.MAX_VALUE, "the retried host delivers values");
      assertEquals(0, ledger.lost(), ledger.counts());
      assertEquals(0, ledger.duplicated(), ledger.counts());
      assertEquals(0, ledger.reordered(), ledger.counts());
      assertEquals(0, ledger.refusedCount(), ledger.counts());
      assertEquals(1, ledger.tagSwitches(), "the worker, then the retried host: never both");
    }
  }

  @Test
  void redisKilledWhileAFailedDeclarationIsUndoneAndWhileItsRetryIsMadeLosesNothing(@TempDir Path dir) throws Exception {
    int before = FaultMode.current().idsPerRun / 4;
    int after = FaultMode.current().idsPerRun / 4;
    String name = "retried-redis-kill";
    TopologyKeys keys = new TopologyKeys(name);
    Duration lease = Duration.ofSeconds(2);
    AtomicReference<Ledger> sink = new AtomicReference<>();
    EventBlock<Long> ids = new EventBlock<>();
    Ledger ledger = new Ledger(0, before + after);
    sink.set(ledger);
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.AOF_ALWAYS, dir);
        FaultProxy proxy = new FaultProxy(redis.port())) {
      OptimusCore observer = Cores.builder(redis.url(), name, StreamTopology.WIDE_RETENTION, null)
          .hosts(List.of()).leaseTime(lease).build();
      OptimusCore holder = Cores.builder(redis.url(), name, StreamTopology.WIDE_RETENTION, null)
          .hosts(List.of("stamp")).leaseTime(lease).build();
      OptimusCore declaring = Cores.builder(proxy.url(), name, StreamTopology.WIDE_RETENTION, null).leaseTime(lease).build();
      try {
        Reader<Long> results = linked(observer, ids, 0).reader();
        linked(holder, new EventBlock<>(), 1);
        Source<Long> declaredIds = declaring.source("ids", new EventBlock<Long>());
        observer.start();
        holder.start();
        declaring.start();
        Chain<Long, Long> chain = declaring.<Long, Long>chain("pre", id -> id)
            .then(declaring.chain("stamp", id -> 2 * StreamTopology.GENERATION + id));
        LedgerFeed.start(results, sink, name);
        for (long id = 0; id < before; id++) ids.publish(id); // accepted: they wait in the input of 'pre', which nobody hosts

        // 1. the declaration claims 'pre', is refused 'stamp', and Redis is killed as it gives 'pre' back
        CountDownLatch killedInUndo = proxy.beforeNextClientWriteContaining(redis::kill, ONE_KEY_RELEASE, keys.hostLease("pre"));
        CompletableFuture<Long> restartedInUndo = restartOnce(redis, killedInUndo);
        long started = System.nanoTime();
        IllegalStateException refused = assertThrows(IllegalStateException.class, () -> declaredIds.then(chain),
            "another core holds the host lease of 'stamp'");
        long refusedIn = System.nanoTime() - started;
        assertTrue(killedInUndo.await(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS), "Redis was killed as the failed declaration gave the lease of 'pre' back");
        long undoOutage = restartedInUndo.get(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS);
        assertDeclarationRefused(refused.getMessage(), "stamp");
        holder.close(); // the other host is gone: its lease is released

        // 2. the retry claims both leases, and Redis is killed as it does
        CountDownLatch killedInRetry = proxy.beforeNextClientWriteContaining(redis::kill, TWO_KEY_CLAIM,
            keys.hostLease("pre"), keys.hostLease("stamp"));
        CompletableFuture<Long> restartedInRetry = restartOnce(redis, killedInRetry);
        long retried = System.nanoTime();
        Source<Long> hosted = declaredIds.then(chain);
        long retriedIn = System.nanoTime() - retried;
        assertTrue(killedInRetry.await(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS), "Redis was killed as the retry claimed the host leases");
        long retryOutage = restartedInRetry.get(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS);
        for (long id = before; id < before + after; id++) {
          try {
            ids.publish(id);
          } catch (RuntimeException e) {
            ledger.refused(id);
          }
        }
        boolean all = ledger.awaitAll(FaultMode.PATIENCE);
        Bounded.hold(Duration.ofMillis(300)); // duplicates would come right behind
        Set<String> serving = Set.copyOf(declaring.serviceNames());
        String preHolder;
        try (Jedis raw = redis.client()) {
          preHolder = raw.get(keys.hostLease("pre"));
          declaring.close();
          observer.close();
          Set<String> leasesLeft = Leftovers.keys(raw, keys.hostLeases());
          Figures.report("redis SIGKILLed (AOF always) while a failed declaration was undone (down " + Figures.seconds(undoOutage)
              + "; refused after " + Figures.seconds(refusedIn) + ") and while its retry claimed its leases (down "
              + Figures.seconds(retryOutage) + "; the retry took " + Figures.seconds(retriedIn) + "): " + ledger.counts()
              + ", " + before + " of them accepted before the first kill; " + leasesLeft.size() + " host leases left after close");
          assertTrue(all, "every value arrives: " + ledger.counts());
          assertEquals(0, ledger.lost(), ledger.counts());
          assertEquals(0, ledger.duplicated(), ledger.counts());
          assertEquals(0, ledger.reordered(), ledger.counts());
          assertEquals(0, ledger.refusedCount(), ledger.counts());
          assertEquals(Set.of("pre", "stamp"), serving, "the retry hosts both services of the chain here");
          assertTrue(hosted != null && preHolder != null, "the retry holds the host lease of 'pre'");
          assertEquals(Set.of(), leasesLeft, "host leases left behind after every core closed");
        }
      } finally {
        declaring.close();
        holder.close();
        observer.close();
      }
    }
  }

  @Test
  void redisKilledWhileARefusedTemplateIsTakenBackAndWhileItIsMadeAgain(@TempDir Path dir) throws Exception {
    int calls = 200;
    String name = "retried-template-kill";
    TopologyKeys keys = new TopologyKeys(name);
    Duration lease = Duration.ofSeconds(2);
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.AOF_ALWAYS, dir);
        FaultProxy proxy = new FaultProxy(redis.port())) {
      OptimusCore holder = Cores.builder(redis.url(), name, 1024, null).leaseTime(lease).build();
      OptimusCore declaring = Cores.builder(proxy.url(), name, 1024, null).leaseTime(lease).build();
      try {
        holder.<Long, Long>chain("below", x -> -x).toBlock();
        holder.start();
        declaring.start();
        Chain<Long, Long> above = declaring.chain("above", x -> x + 1);
        Chain<Long, Long> below = declaring.chain("below", x -> -x);

        // 1. 'above' is bound and runs, 'below' is refused, and Redis is killed as 'above' is taken back
        CountDownLatch killedInUndo = proxy.beforeNextClientWriteContaining(redis::kill, ONE_KEY_RELEASE, keys.hostLease("above"));
        CompletableFuture<Long> restartedInUndo = restartOnce(redis, killedInUndo);
        long started = System.nanoTime();
        IllegalStateException refused = assertThrows(IllegalStateException.class,
            () -> declaring.ifThenElse((Long x) -> x >= 0, above, below), "another core holds the host lease of 'below'");
        long refusedIn = System.nanoTime() - started;
        assertTrue(killedInUndo.await(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS), "Redis was killed as the refused template gave the lease of 'above' back");
        long undoOutage = restartedInUndo.get(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS);
        assertDeclarationRefused(refused.getMessage(), "below");
        holder.close();

        // 2. the same template again, and Redis is killed as it claims the lease of 'above'
        CountDownLatch killedInRetry = proxy.beforeNextClientWriteContaining(redis::kill, ONE_KEY_CLAIM, keys.hostLease("above"));
        CompletableFuture<Long> restartedInRetry = restartOnce(redis, killedInRetry);
        long retried = System.nanoTime();
        Block<Long, Long> chosen = declaring.ifThenElse((Long x) -> x >= 0, above, below).toBlock();
        long retriedIn = System.nanoTime() - retried;
        assertTrue(killedInRetry.await(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS), "Redis was killed as the retry claimed the lease of 'above'");
        long retryOutage = restartedInRetry.get(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS);
        int wrong = 0;
        for (long i = 0; i < calls; i++) {
          long x = i % 2 == 0 ? i : -i;
          if (chosen.process(x) != (x >= 0 ? x + 1 : -x)) wrong++;
        }
        Set<String> serving = Set.copyOf(declaring.serviceNames());
        try (Jedis raw = redis.client()) {
          declaring.close();
          Set<String> leasesLeft = Leftovers.keys(raw, keys.hostLeases());
          Figures.report("redis SIGKILLed (AOF always) while a refused template was taken back (down " + Figures.seconds(undoOutage)
              + "; refused after " + Figures.seconds(refusedIn) + ") and while it was made again (down " + Figures.seconds(retryOutage)
              + "; the retry took " + Figures.seconds(retriedIn) + "): " + calls + " calls, " + wrong + " wrong; hosting " + serving
              + "; " + leasesLeft.size() + " host leases left after close");
          assertEquals(0, wrong, "every call of the template made again returns its branch's value");
          assertTrue(serving.containsAll(Set.of("above", "below")), "both parts run here: " + serving);
          assertEquals(Set.of(), leasesLeft, "host leases left behind after every core closed");
        }
      } finally {
        declaring.close();
        holder.close();
      }
    }
  }

  @Test
  void closeWhileADeclarationWaitsOnAFrozenRedisEndsInTimeAndLeavesNothing() throws Exception {
    String name = "retried-frozen";
    Duration shutdown = Duration.ofSeconds(5);
    TopologyKeys keys = new TopologyKeys(name);
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null);
        FaultProxy proxy = new FaultProxy(redis.port());
        WorkerJvm host = WorkerJvm.start(name + "-host", "stream", redis.url(), name,
            Integer.toString(StreamTopology.WIDE_RETENTION), "1")) {
      host.awaitReady();
      int threadsBefore = Leftovers.threadsOf(name).size();
      OptimusCore declaring = OptimusCore.builder()
          .config(CoreConfig.builder().name(name).shutdownTimeout(shutdown).build())
          .redis(proxy.url()).build();
      CompletableFuture<Object> declaration = new CompletableFuture<>();
      try {
        Source<Long> declaredIds = declaring.source("ids", new EventBlock<Long>());
        Chain<Long, Long> stamp = declaring.chain("stamp", id -> 2 * StreamTopology.GENERATION + id);
        declaring.start();
        int connectionsOpen = proxy.openConnections();
        // the declaration claims the lease the worker holds, and the network freezes as it asks
        CountDownLatch frozen = proxy.beforeNextClientWriteContaining(proxy::freeze, ONE_KEY_CLAIM, keys.hostLease("stamp"));
        Thread declarer = new Thread(() -> {
          try {
            declaration.complete(declaredIds.then(stamp));
          } catch (Throwable e) {
            declaration.complete(e);
          }
        }, "fault-declarer");
        declarer.start();
        assertTrue(frozen.await(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS), "the declaration claimed the lease of 'stamp'");
        long closing = System.nanoTime();
        declaring.close();
        long closeTook = System.nanoTime() - closing;
        List<String> threadsAtReturn = Leftovers.threadsOf(name);
        Object outcome = declaration.get(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS);
        long declarationEnded = System.nanoTime() - closing;
        long threadsGone = Bounded.await(Duration.ofSeconds(10), () -> Leftovers.threadsOf(name).size() <= threadsBefore);
        long connectionsGone = Bounded.await(Duration.ofSeconds(10), () -> proxy.openConnections() == 0);
        List<String> threadsLeft = Leftovers.threadsOf(name);
        int connectionsLeft = proxy.openConnections();
        Figures.report("close() while a declaration waits on a frozen Redis: close " + Figures.seconds(closeTook)
            + " (shutdownTimeout " + Figures.seconds(shutdown) + "), the declaration ended " + Figures.seconds(declarationEnded)
            + " after the close began with " + describe(outcome) + "; left: " + (threadsLeft.size() - threadsBefore)
            + " threads of the core (" + threadsBefore + " before it; " + (threadsAtReturn.size() - threadsBefore)
            + " as close() returned), " + connectionsLeft + " of " + connectionsOpen
            + " proxied connections (gone " + (connectionsGone < 0 ? "never" : "after " + Figures.seconds(connectionsGone)) + ")"
            + ", threads gone " + (threadsGone < 0 ? "never" : "after " + Figures.seconds(threadsGone)));
        assertTrue(closeTook <= shutdown.toNanos(), "close() took " + Figures.seconds(closeTook));
        assertInstanceOf(CoreClosedException.class, outcome, "the waiting declaration ends with the close: " + describe(outcome));
        assertEquals(threadsBefore, threadsAtReturn.size(), "threads of the core still running as close() returned: " + threadsAtReturn);
        assertEquals(threadsBefore, threadsLeft.size(), "threads of the core left: " + threadsLeft);
        assertEquals(0, connectionsLeft, "connections left open through the proxy");
      } finally {
        proxy.thaw();
        declaring.close();
      }
    }
  }

  @Test
  void anInterruptEndsADeclarationWaitingOnAFrozenRedisAndItCanBeMadeAgain() throws Exception {
    String name = "retried-frozen-interrupt";
    TopologyKeys keys = new TopologyKeys(name);
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null);
        FaultProxy proxy = new FaultProxy(redis.port());
        OptimusCore declaring = Cores.builder(proxy.url(), name, 1024, null).build()) {
      declaring.start();
      Chain<Long, Long> late = declaring.chain("late", x -> x + 1);
      CountDownLatch frozen = proxy.beforeNextClientWriteContaining(proxy::freeze, ONE_KEY_CLAIM, keys.hostLease("late"));
      CompletableFuture<Object> declaration = new CompletableFuture<>();
      Thread declarer = new Thread(() -> {
        try {
          declaration.complete(late.toBlock());
        } catch (Throwable e) {
          declaration.complete(e);
        }
      }, "fault-declarer");
      declarer.start();
      assertTrue(frozen.await(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS), "the declaration claimed the lease of 'late'");
      long interrupted = System.nanoTime();
      declarer.interrupt();
      Object outcome = declaration.get(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS);
      long ended = System.nanoTime() - interrupted;
      proxy.thaw();
      long retried = System.nanoTime();
      Block<Long, Long> block = late.toBlock();
      long retriedIn = System.nanoTime() - retried;
      long answer = block.process(1L);
      Figures.report("an interrupt of a declaration waiting on a frozen Redis: it ended " + Figures.seconds(ended)
          + " after the interrupt with " + describe(outcome) + "; made again after the thaw in " + Figures.seconds(retriedIn)
          + ", its block answered " + answer);
      assertTrue(outcome instanceof dev.prime.PrimeException && !(outcome instanceof CoreClosedException),
          "the interrupted declaration fails with a PrimeException saying so: " + describe(outcome));
      assertTrue(ended < Duration.ofSeconds(2).toNanos(), "the interrupt ends the wait within about a second: " + Figures.seconds(ended));
      assertEquals(2L, answer, "the same declaration works once Redis answers again");
    }
  }

  @Test
  void aFlagAlreadySetEndsADeclarationOrAStartOnAFrozenRedisAtOnce() throws Exception {
    String name = "retried-frozen-flag";
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null);
        FaultProxy proxy = new FaultProxy(redis.port());
        OptimusCore declaring = Cores.builder(proxy.url(), name, 1024, null).build();
        OptimusCore starting = Cores.builder(proxy.url(), name + "-start", 1024, null).build()) {
      declaring.start();
      Chain<Long, Long> late = declaring.chain("late", x -> x + 1);
      starting.chain("other", (Long x) -> x).toBlock();
      proxy.freeze();
      CompletableFuture<Object[]> declared = flagged("fault-flagged-declarer", late::toBlock);
      CompletableFuture<Object[]> started = flagged("fault-flagged-starter", () -> {
        starting.start();
        return "started";
      });
      Object[] declaration = declared.get(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS);
      Object[] start = started.get(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS);
      proxy.thaw();
      long answer = late.toBlock().process(1L);
      Figures.report("a flag already set as a declaration or a start() begins on a frozen Redis: the declaration ended after "
          + Figures.seconds((Long) declaration[1]) + " with " + describe(declaration[0]) + " (flag kept " + declaration[2]
          + "), start() after " + Figures.seconds((Long) start[1]) + " with " + describe(start[0]) + " (flag kept " + start[2]
          + "); made again after the thaw, the block answered " + answer);
      for (Object[] outcome : List.of(declaration, start)) {
        assertTrue(outcome[0] instanceof dev.prime.PrimeException && !(outcome[0] instanceof CoreClosedException)
            && ((Throwable) outcome[0]).getMessage().contains("interrupted"), "fails with a PrimeException saying so: " + describe(outcome[0]));
        assertTrue((Long) outcome[1] < Duration.ofSeconds(1).toNanos(), "the flag ends it at once: " + Figures.seconds((Long) outcome[1]));
        assertEquals(Boolean.TRUE, outcome[2], "the flag is kept");
      }
      assertEquals(2L, answer, "the same declaration works once Redis answers again");
    }
  }

  @Test
  void aClaimInterruptedAfterRedisGrantedItGivesTheLeaseBack() throws Exception {
    String name = "retried-granted-interrupt";
    TopologyKeys keys = new TopologyKeys(name);
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null);
        FaultProxy proxy = new FaultProxy(redis.port());
        Jedis raw = redis.client();
        OptimusCore declaring = Cores.builder(proxy.url(), name, 1024, null).build()) {
      declaring.start();
      // a first claim loads the claim script, so the claim below is one EVALSHA that Redis runs
      assertEquals(1L, declaring.<Long, Long>chain("warm", x -> x).toBlock().process(1L));
      Chain<Long, Long> late = declaring.chain("late", x -> x + 1);
      String lease = keys.hostLease("late");
      // Redis gets the claim and grants it; its answer never reaches the declaring core
      CountDownLatch forwarded = proxy.holdAnswersAfterNextClientWriteContaining(ONE_KEY_CLAIM, lease);
      CompletableFuture<Object> declaration = new CompletableFuture<>();
      Thread declarer = new Thread(() -> {
        try {
          declaration.complete(late.toBlock());
        } catch (Throwable e) {
          declaration.complete(e);
        }
      }, "fault-declarer");
      declarer.start();
      assertTrue(forwarded.await(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS), "the declaration sent its claim of 'late'");
      long granted = Bounded.await(Duration.ofSeconds(10), () -> raw.exists(lease));
      long interrupted = System.nanoTime();
      declarer.interrupt();
      Object outcome = declaration.get(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS);
      long ended = System.nanoTime() - interrupted;
      String holder = raw.get(lease);
      long leaseLeft = raw.pttl(lease);
      long retried = System.nanoTime();
      long answer = late.toBlock().process(1L);
      long retriedIn = System.nanoTime() - retried;
      Figures.report("a claim interrupted after Redis granted it (its answer held back): granted " + (granted >= 0) + ", the declaration ended "
          + Figures.seconds(ended) + " after the interrupt with " + describe(outcome) + "; the lease then "
          + (holder == null ? "released" : "held by " + holder + " for " + leaseLeft + " ms more") + "; made again in "
          + Figures.seconds(retriedIn) + ", its block answered " + answer);
      assertTrue(granted >= 0, "Redis granted the claim");
      assertTrue(outcome instanceof dev.prime.PrimeException && !(outcome instanceof CoreClosedException),
          "the interrupted declaration fails with a PrimeException saying so: " + describe(outcome));
      assertTrue(ended < Duration.ofSeconds(2).toNanos(), "the interrupt ends the declaration within about a second: " + Figures.seconds(ended));
      assertEquals(null, holder, "the lease the failed claim was granted is given back, not held for " + leaseLeft + " ms more");
      assertEquals(2L, answer, "the same declaration works again");
    }
  }

  /** Runs {@code action} on a new thread whose interrupt flag is set first: what it returned or threw, its nanoseconds, whether the flag was kept. */
  private static CompletableFuture<Object[]> flagged(String threadName, java.util.concurrent.Callable<Object> action) {
    CompletableFuture<Object[]> outcome = new CompletableFuture<>();
    Thread thread = new Thread(() -> {
      Thread.currentThread().interrupt();
      long began = System.nanoTime();
      Object result;
      try {
        result = action.call();
      } catch (Throwable e) {
        result = e;
      }
      long took = System.nanoTime() - began;
      outcome.complete(new Object[] {result, took, Thread.interrupted()});
    }, threadName);
    thread.start();
    return outcome;
  }

  /** Declares {@code ids → pre → stamp} (stamp marking with {@code generation}) on {@code core}. */
  private static Source<Long> linked(PrimeCore core, EventBlock<Long> ids, int generation) {
    Chain<Long, Long> pre = core.chain("pre", id -> id);
    Chain<Long, Long> stamp = core.chain("stamp", id -> generation * StreamTopology.GENERATION + id);
    return core.source("ids", ids).then(pre.then(stamp));
  }

  /** Restarts {@code redis} with its data once {@code killed} opens; the outage's nanoseconds. */
  private static CompletableFuture<Long> restartOnce(RedisProcess redis, CountDownLatch killed) {
    return CompletableFuture.supplyAsync(() -> {
      try {
        if (!killed.await(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS)) return -1L;
      } catch (InterruptedException e) {
        Thread.currentThread().interrupt();
        return -1L;
      }
      long down = System.nanoTime();
      redis.restart(true);
      return System.nanoTime() - down;
    });
  }

  /** A refusal of a declaration after start() names the service and says the declaration can be made again. */
  private static void assertDeclarationRefused(String message, String service) {
    assertTrue(message != null && message.contains("already hosted by") && message.contains("'" + service + "'"), message);
    assertTrue(message.contains("can be made again"), message);
  }

  private static String describe(Object outcome) {
    return outcome instanceof Throwable e ? e.getClass().getSimpleName() + " (" + e.getMessage() + ")" : "no exception: " + outcome;
  }
}

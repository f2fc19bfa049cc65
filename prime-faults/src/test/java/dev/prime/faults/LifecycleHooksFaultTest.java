package dev.prime.faults;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreClosedException;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.optimus.OptimusCore;
import java.nio.file.Path;
import java.time.Duration;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicInteger;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * {@code whenRunning} hooks of an Optimus core whose redis-server is killed (SIGKILL) while
 * {@code start()} waits for it: restarted, the start completes and runs every hook's
 * {@code onStart} once; left down, a {@code close()} ends the start, no {@code onStart} runs, and
 * either way every hook's {@code onClose} runs exactly once, after its {@code onStart} if that ran,
 * and {@code close()} ends within its shutdown timeout, leaving no thread of the core.
 */
class LifecycleHooksFaultTest {
  /** How a one-key {@code HOST_CLAIM} script call starts on the wire: EVALSHA, its hash, 1, the key, the instance, the lease. */
  private static final String ONE_KEY_CLAIM = "*6\r\n$7\r\nEVALSHA\r\n";
  private static final Duration SHUTDOWN = Duration.ofSeconds(5);

  @Test
  void redisKilledDuringStartAndRestarted(@TempDir Path dir) throws Exception {
    String name = "hooks-redis-back";
    Hooks hooks = new Hooks();
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.AOF_ALWAYS, dir);
        FaultProxy proxy = new FaultProxy(redis.port())) {
      OptimusCore core = core(proxy.url(), name);
      try {
        StreamTopology.declareStream(core, new EventBlock<>(), 1, false);
        for (int i = 0; i < 3; i++) hooks.add(core);
        CountDownLatch killed = proxy.beforeNextClientWriteContaining(redis::kill, ONE_KEY_CLAIM, new TopologyKeys(name).hostLease("stamp"));
        CompletableFuture<Object> start = startOn(core);
        assertTrue(killed.await(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS), "Redis was killed as start() claimed its host lease");
        hooks.add(core); // while start() waits for Redis
        long down = System.nanoTime();
        redis.restart(true);
        long restarted = System.nanoTime();
        Object started = start.get(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS);
        long startEnded = System.nanoTime() - restarted;
        hooks.add(core); // after start(): its onStart runs at once
        List<Integer> startsBeforeClose = hooks.starts();
        long closing = System.nanoTime();
        core.close();
        long closeTook = System.nanoTime() - closing;
        long threadsGone = Bounded.await(Duration.ofSeconds(5), () -> Leftovers.threadsOf(name).isEmpty());
        Figures.report("whenRunning, Redis SIGKILLed during start() and restarted (down " + Figures.seconds(restarted - down)
            + "): start() " + describe(started) + " " + Figures.seconds(startEnded) + " after the restart; onStart ran "
            + startsBeforeClose + ", onClose " + hooks.closes() + " times per hook, " + hooks.closedBeforeStarting.get()
            + " started after their close; close() " + Figures.seconds(closeTook) + ", threads left " + Leftovers.threadsOf(name).size());
        assertEquals("started", describe(started), "start() completes once Redis is back");
        assertEquals(List.of(1, 1, 1, 1, 1), startsBeforeClose, "each hook's onStart runs once");
        assertEquals(List.of(1, 1, 1, 1, 1), hooks.closes(), "each hook's onClose runs once");
        assertEquals(0, hooks.closedBeforeStarting.get(), "no onStart after its onClose");
        assertTrue(closeTook <= SHUTDOWN.toNanos(), "close() took " + Figures.seconds(closeTook));
        assertTrue(threadsGone >= 0, "threads left: " + Leftovers.threadsOf(name));
      } finally {
        core.close();
      }
    }
  }

  @Test
  void redisKilledDuringStartAndLeftDown() throws Exception {
    String name = "hooks-redis-down";
    Hooks hooks = new Hooks();
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null);
        FaultProxy proxy = new FaultProxy(redis.port())) {
      OptimusCore core = core(proxy.url(), name);
      try {
        StreamTopology.declareStream(core, new EventBlock<>(), 1, false);
        for (int i = 0; i < 3; i++) hooks.add(core);
        CountDownLatch killed = proxy.beforeNextClientWriteContaining(redis::kill, ONE_KEY_CLAIM, new TopologyKeys(name).hostLease("stamp"));
        CompletableFuture<Object> start = startOn(core);
        assertTrue(killed.await(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS), "Redis was killed as start() claimed its host lease");
        hooks.add(core); // while start() waits for Redis
        long closing = System.nanoTime();
        core.close();
        long closeTook = System.nanoTime() - closing;
        Object started = start.get(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS);
        long startEnded = System.nanoTime() - closing;
        long threadsGone = Bounded.await(Duration.ofSeconds(5), () -> Leftovers.threadsOf(name).isEmpty());
        Figures.report("whenRunning, Redis SIGKILLed during start() and left down: close() " + Figures.seconds(closeTook)
            + ", start() ended " + Figures.seconds(startEnded) + " after the close began with " + describe(started)
            + "; onStart ran " + hooks.starts() + ", onClose " + hooks.closes() + " times per hook, " + hooks.closedBeforeStarting.get()
            + " started after their close; threads left " + Leftovers.threadsOf(name).size());
        assertEquals(List.of(0, 0, 0, 0), hooks.starts(), "no onStart runs: the start never completed");
        assertEquals(List.of(1, 1, 1, 1), hooks.closes(), "each hook's onClose runs once, also if it never started");
        assertTrue(closeTook <= SHUTDOWN.toNanos(), "close() took " + Figures.seconds(closeTook));
        assertTrue(started instanceof RuntimeException, "start() fails once the core is closed: " + describe(started));
        assertTrue(threadsGone >= 0, "threads left: " + Leftovers.threadsOf(name));
      } finally {
        core.close();
      }
    }
  }

  @Test
  void networkFrozenDuringStartAndTheCoreClosed() throws Exception {
    String name = "hooks-frozen";
    Hooks hooks = new Hooks();
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null);
        FaultProxy proxy = new FaultProxy(redis.port())) {
      OptimusCore core = core(proxy.url(), name);
      try {
        StreamTopology.declareStream(core, new EventBlock<>(), 1, false);
        for (int i = 0; i < 3; i++) hooks.add(core);
        CountDownLatch frozen = proxy.beforeNextClientWriteContaining(proxy::freeze, ONE_KEY_CLAIM, new TopologyKeys(name).hostLease("stamp"));
        CompletableFuture<Object> start = startOn(core);
        assertTrue(frozen.await(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS), "the network froze as start() claimed its host lease");
        int connectionsOpen = proxy.openConnections();
        long closing = System.nanoTime();
        core.close();
        long closeTook = System.nanoTime() - closing;
        List<String> threadsAtReturn = Leftovers.threadsOf(name);
        Object started = start.get(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS);
        long startEnded = System.nanoTime() - closing;
        long connectionsGone = Bounded.await(Duration.ofSeconds(10), () -> proxy.openConnections() == 0);
        Figures.report("whenRunning, network frozen during start(), core closed: close() " + Figures.seconds(closeTook)
            + ", start() ended " + Figures.seconds(startEnded) + " after the close began with " + describe(started) + "; onStart ran "
            + hooks.starts() + ", onClose " + hooks.closes() + " times per hook; " + threadsAtReturn.size()
            + " threads of the core as close() returned, " + proxy.openConnections() + " of " + connectionsOpen
            + " proxied connections left (gone " + (connectionsGone < 0 ? "never" : "after " + Figures.seconds(connectionsGone)) + ")");
        assertEquals(List.of(0, 0, 0), hooks.starts(), "no onStart runs: the start never completed");
        assertEquals(List.of(1, 1, 1), hooks.closes(), "each hook's onClose runs once");
        assertTrue(started instanceof CoreClosedException, "start() ends with the close: " + describe(started));
        assertTrue(closeTook <= SHUTDOWN.toNanos(), "close() took " + Figures.seconds(closeTook));
        assertEquals(List.of(), threadsAtReturn, "threads of the core still running as close() returned");
        assertTrue(connectionsGone >= 0, proxy.openConnections() + " connections left open through the proxy");
      } finally {
        proxy.thaw();
        core.close();
      }
    }
  }

  @Test
  void redisKilledWhileAHookStartsInStart() throws Exception {
    String name = "hooks-redis-killed-in-hook";
    Hooks hooks = new Hooks();
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null)) {
      OptimusCore core = core(redis.url(), name);
      try {
        EventBlock<Long> ids = new EventBlock<>();
        core.source("ids", ids).reader();
        hooks.add(core);
        CountDownLatch killed = new CountDownLatch(1);
        AtomicInteger publishing = new AtomicInteger();
        AtomicInteger closedWhilePublishing = new AtomicInteger();
        core.whenRunning("publisher", () -> {
          redis.kill(); // Redis dies as this hook starts, inside start()
          killed.countDown();
          publishing.incrementAndGet();
          try {
            ids.publish(1L); // waits for Redis until the close ends it
          } finally {
            publishing.decrementAndGet();
          }
        }, () -> {
          if (publishing.get() > 0) closedWhilePublishing.incrementAndGet();
          hooks.publisherClosed.incrementAndGet();
        });
        hooks.add(core);
        CompletableFuture<Object> start = startOn(core);
        assertTrue(killed.await(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS), "the second hook's start killed Redis");
        long closing = System.nanoTime();
        core.close();
        long closeTook = System.nanoTime() - closing;
        Object started = start.get(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS);
        long startEnded = System.nanoTime() - closing;
        long publisherClosed = Bounded.await(Duration.ofSeconds(10), () -> hooks.publisherClosed.get() > 0);
        long threadsGone = Bounded.await(Duration.ofSeconds(5), () -> Leftovers.threadsOf(name).isEmpty());
        Figures.report("whenRunning, Redis SIGKILLed by a hook's onStart inside start(), its publish waiting: close() "
            + Figures.seconds(closeTook) + " (shutdownTimeout " + Figures.seconds(SHUTDOWN) + "), start() ended "
            + Figures.seconds(startEnded) + " after the close began with " + describe(started) + "; onStart ran " + hooks.starts()
            + " and onClose " + hooks.closes() + " times for the other hooks, the publishing hook's onClose "
            + hooks.publisherClosed.get() + " times (" + closedWhilePublishing.get() + " while its onStart still ran, "
            + (publisherClosed < 0 ? "never" : Figures.seconds(publisherClosed) + " after close() returned") + "); threads left "
            + Leftovers.threadsOf(name).size());
        assertEquals(List.of(1, 0), hooks.starts(), "the hook before the publishing one started, the one after it never");
        assertEquals(List.of(1, 1), hooks.closes(), "each other hook's onClose runs once");
        assertEquals(1, hooks.publisherClosed.get(), "the publishing hook's onClose runs once");
        assertEquals(0, closedWhilePublishing.get(), "and only after its onStart returned");
        assertTrue(closeTook <= 3 * SHUTDOWN.toNanos(), "close() took " + Figures.seconds(closeTook));
        assertTrue(threadsGone >= 0, "threads left: " + Leftovers.threadsOf(name));
      } finally {
        core.close();
      }
    }
  }

  private static OptimusCore core(String url, String name) {
    CoreConfig config = CoreConfig.builder().name(name).shutdownTimeout(SHUTDOWN).sourceRetention(StreamTopology.WIDE_RETENTION).build();
    return OptimusCore.builder().config(config).redis(url).build();
  }

  /** Runs {@code start()} on a thread of its own: "started", or what it threw. */
  private static CompletableFuture<Object> startOn(OptimusCore core) {
    CompletableFuture<Object> outcome = new CompletableFuture<>();
    Thread starter = new Thread(() -> {
      try {
        core.start();
        outcome.complete("started");
      } catch (Throwable e) {
        outcome.complete(e);
      }
    }, "fault-starter");
    starter.setDaemon(true);
    starter.start();
    return outcome;
  }

  private static String describe(Object outcome) {
    return outcome instanceof Throwable e ? e.getClass().getSimpleName() + " (" + e.getMessage() + ")" : String.valueOf(outcome);
  }

  /** Hooks that count their starts and closes. */
  private static final class Hooks {
    private final List<AtomicInteger> starts = new ArrayList<>();
    private final List<AtomicInteger> closes = new ArrayList<>();
    final AtomicInteger closedBeforeStarting = new AtomicInteger();
    final AtomicInteger publisherClosed = new AtomicInteger();

    synchronized void add(OptimusCore core) {
      AtomicInteger started = new AtomicInteger();
      AtomicInteger closed = new AtomicInteger();
      starts.add(started);
      closes.add(closed);
      core.whenRunning("hook-" + starts.size(), () -> {
        if (closed.get() > 0) closedBeforeStarting.incrementAndGet();
        started.incrementAndGet();
      }, closed::incrementAndGet);
    }

    synchronized List<Integer> starts() {
      return starts.stream().map(AtomicInteger::get).toList();
    }

    synchronized List<Integer> closes() {
      return closes.stream().map(AtomicInteger::get).toList();
    }
  }
}

package dev.prime.faults;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.Reader;
import dev.prime.optimus.OptimusCore;
import java.net.InetSocketAddress;
import java.net.Socket;
import java.net.URI;
import java.time.Duration;
import java.util.List;
import java.util.Set;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicReference;
import org.junit.jupiter.api.Test;
import redis.clients.jedis.Jedis;

/**
 * What {@code close()} leaves behind, counted from outside: no thread of the core, no Redis
 * connection under its client name (CLIENT LIST), no reader or reply list (classic); and
 * {@code close()} called from a hosted service's own thread returns at once, without an
 * exception, and stops the core's embedded redis-server (issue 9 item 9).
 */
class CloseFaultTest {

  @Test
  void closeLeavesNoThreadsConnectionsOrKeys() throws Exception {
    String name = "close-leftovers";
    TopologyKeys keys = new TopologyKeys(name);
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null); Jedis raw = redis.client()) {
      OptimusCore core = Cores.core(redis.url(), name, 1024, "stamp", "echo");
      AtomicReference<Ledger> sink = new AtomicReference<>();
      EventBlock<Long> ids = new EventBlock<>();
      var stream = StreamTopology.declareStream(core, ids, 0, true);
      List<Reader<Long>> readers = List.of(stream.output().reader(), stream.output().reader());
      Block<Long, Long> echo = core.<Long, Long>chain("echo", x -> x).toBlock();
      core.start();
      LedgerFeed.start(stream.observer(), sink, name);
      Ledger ledger = new Ledger(0, 100);
      sink.set(ledger);
      for (long id = 0; id < 100; id++) ids.publish(id);
      assertTrue(ledger.awaitAll(FaultMode.PATIENCE), ledger.counts());
      for (long i = 0; i < 20; i++) assertEquals(i, echo.process(i));
      assertTrue(readers.get(0).take(Duration.ofSeconds(10)).isPresent(), "a reader reads");
      long clientsBefore = Leftovers.clientsOf(raw, name);
      int readerKeysBefore = Leftovers.keys(raw, keys.readerLists()).size();
      int replyKeysBefore = Leftovers.keys(raw, keys.replyLists()).size();

      long started = System.nanoTime();
      core.close();
      long took = System.nanoTime() - started;
      long threadsGone = Bounded.await(Duration.ofSeconds(5), () -> Leftovers.threadsOf(name).isEmpty());
      List<String> threads = Leftovers.threadsOf(name);
      long clients = Leftovers.clientsOf(raw, name);
      Set<String> readerKeys = Leftovers.keys(raw, keys.readerLists());
      Set<String> replyKeys = Leftovers.keys(raw, keys.replyLists());
      long registered = raw.smembers(keys.sourceReaders("ids")).stream().filter(m -> m.contains(":rdr:")).count();
      Figures.report("close: " + Figures.seconds(took) + " (threads gone " + (threadsGone < 0 ? "never" : "after " + Figures.seconds(threadsGone))
          + "); left: " + threads.size() + " threads, " + clients + " of " + clientsBefore + " connections, "
          + readerKeys.size() + " of " + readerKeysBefore + " reader lists, " + replyKeys.size() + " of " + replyKeysBefore
          + " reply lists, " + registered + " registered readers");
      assertEquals(List.of(), threads, "threads left behind");
      assertEquals(0, clients, "connections left behind");
      assertEquals(Set.of(), readerKeys, "reader lists left behind");
      assertEquals(Set.of(), replyKeys, "reply lists left behind");
      assertEquals(0, registered, "readers still registered with the source");
      assertTrue(took < core.config().shutdownTimeout().toNanos(), "close took " + Figures.seconds(took));
    }
  }

  @Test
  void closeFromAHostedServiceThreadReturnsAndStopsTheEmbeddedRedis() throws Exception {
    String name = "close-inside";
    Duration shutdown = Duration.ofSeconds(10);
    OptimusCore core = new OptimusCore(CoreConfig.builder().name(name).shutdownTimeout(shutdown).build());
    URI redis = URI.create(core.getRedisUrl());
    CompletableFuture<String> outcome = new CompletableFuture<>();
    try {
      EventBlock<Long> numbers = new EventBlock<>();
      core.source("numbers", numbers).listen(x -> {
        long started = System.nanoTime();
        try {
          core.close();
          outcome.complete("returned in " + Figures.seconds(System.nanoTime() - started));
        } catch (Throwable e) {
          outcome.complete("threw " + e + " after " + Figures.seconds(System.nanoTime() - started));
        }
      });
      core.start();
      numbers.publish(1L);
      String result = outcome.get(shutdown.toSeconds() * 3, TimeUnit.SECONDS);
      long threadsGone = Bounded.await(Duration.ofSeconds(5), () -> Leftovers.threadsOf(name).isEmpty());
      boolean redisAnswers = answers(redis);
      Figures.report("close() from a service thread: " + result + ", core closed " + core.isClosed() + ", threads gone "
          + (threadsGone < 0 ? "never: " + Leftovers.threadsOf(name) : "after " + Figures.seconds(threadsGone))
          + ", embedded redis-server " + (redisAnswers ? "still running" : "stopped"));
      assertTrue(result.startsWith("returned"), result);
      assertTrue(core.isClosed());
      assertTrue(threadsGone >= 0, "threads left: " + Leftovers.threadsOf(name));
      assertFalse(redisAnswers, "the embedded redis-server stops with its core");
      double seconds = Double.parseDouble(result.replaceAll("[^0-9.]", ""));
      assertTrue(seconds < shutdown.toSeconds() / 2.0, "close() from a service thread must not wait out its timeout: " + result);
    } finally {
      core.close();
    }
  }

  @Test
  void closeOnAFrozenRedisStaysWithinAShortShutdownTimeout() throws Exception {
    String name = "close-frozen-short";
    Duration shutdown = Duration.ofMillis(500);
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null);
        FaultProxy proxy = new FaultProxy(redis.port())) {
      OptimusCore core = OptimusCore.builder()
          .config(CoreConfig.builder().name(name).shutdownTimeout(shutdown).sourceRetention(1024).build())
          .redis(proxy.url()).callTimeout(Duration.ofSeconds(10)).build();
      try {
        EventBlock<Long> ids = new EventBlock<>();
        var numbers = core.source("ids", ids);
        Reader<Long> reader = numbers.reader();
        Block<Long, Long> echo = core.<Long, Long>chain("echo", x -> x).toBlock();
        core.start();
        assertEquals(7L, echo.process(7L), "the core works before the freeze");
        ids.publish(1L);
        assertTrue(reader.take(Duration.ofSeconds(10)).isPresent(), "a reader reads before the freeze");
        int connectionsOpen = proxy.openConnections();
        proxy.freeze();
        long started = System.nanoTime();
        core.close();
        long took = System.nanoTime() - started;
        List<String> threadsAtReturn = Leftovers.threadsOf(name);
        long connectionsGone = Bounded.await(Duration.ofSeconds(10), () -> proxy.openConnections() == 0);
        Figures.report("close() on a frozen Redis with shutdownTimeout " + Figures.seconds(shutdown) + ": "
            + Figures.seconds(took) + ", " + threadsAtReturn.size() + " threads of the core as it returned, "
            + "proxied connections (" + connectionsOpen + " before the freeze) gone "
            + (connectionsGone < 0 ? "never" : "after " + Figures.seconds(connectionsGone)));
        assertTrue(took <= shutdown.toNanos(), "close() took " + Figures.seconds(took) + ", shutdownTimeout " + Figures.seconds(shutdown));
        assertEquals(List.of(), threadsAtReturn, "threads of the core still running as close() returned");
        assertTrue(connectionsGone >= 0, "connections left open through the proxy: " + proxy.openConnections());
      } finally {
        proxy.thaw();
        core.close();
      }
    }
  }

  private static boolean answers(URI redis) {
    try (Socket socket = new Socket()) {
      socket.connect(new InetSocketAddress("127.0.0.1", redis.getPort()), 1000);
      return true;
    } catch (java.io.IOException e) {
      return false;
    }
  }
}

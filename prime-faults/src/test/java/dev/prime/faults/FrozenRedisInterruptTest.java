package dev.prime.faults;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreClosedException;
import dev.prime.EventBlock;
import dev.prime.PrimeException;
import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.optimus.OptimusCore;
import java.time.Duration;
import java.util.ArrayList;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.Optional;
import java.util.concurrent.Callable;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;

/**
 * An interrupt ends the wait of Optimus's publish, {@code deadLetters}, {@code trimmedDeadLetters},
 * {@code clearDeadLetters}, a source's {@code reader()} and a reader's {@code missed()} for the
 * answer of a Redis that stopped answering (a frozen network, connections open): each fails at once
 * with a {@code PrimeException} that says it was interrupted (and, for a publish and a clear, that
 * its command may have taken effect), never {@code CoreClosedException}, the flag kept; and each
 * works again after the thaw.
 */
class FrozenRedisInterruptTest {

  @Test
  void anInterruptEndsAPublishOrAReadWaitingOnAFrozenRedisAtOnce() throws Exception {
    String name = "frozen-interrupt";
    try (RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null);
        FaultProxy proxy = new FaultProxy(redis.port());
        OptimusCore core = Cores.builder(proxy.url(), name, 1024, null).build()) {
      EventBlock<Long> ids = new EventBlock<>();
      Source<Long> source = core.source("ids", ids);
      Reader<Long> reader = source.reader();
      core.start();
      ids.publish(1L);
      assertEquals(Optional.of(1L), reader.take(FaultMode.PATIENCE), "a reader reads before the freeze");

      // each operation, and what its write to Redis contains: the proxy freezes just before it forwards it
      Map<String, Callable<Object>> operations = new LinkedHashMap<>();
      Map<String, String[]> writes = new LinkedHashMap<>();
      operations.put("publish", () -> {
        ids.publish(2L);
        return "published";
      });
      writes.put("publish", new String[] {"EVALSHA", "src:ids:log"});
      operations.put("deadLetters", () -> core.deadLetters("ids-service"));
      writes.put("deadLetters", new String[] {"LRANGE", "svc:ids-service:dead"});
      operations.put("trimmedDeadLetters", () -> core.trimmedDeadLetters("ids-service"));
      writes.put("trimmedDeadLetters", new String[] {"GET", "svc:ids-service:dead:trimmed"});
      operations.put("clearDeadLetters", () -> core.clearDeadLetters("ids-service"));
      writes.put("clearDeadLetters", new String[] {"LLEN", "svc:ids-service:dead"});
      operations.put("reader()", source::reader);
      writes.put("reader()", new String[] {"HSET", "src:ids:readers"});
      operations.put("missed()", reader::missed);
      writes.put("missed()", new String[] {"GET", ":missed"});

      List<String> figures = new ArrayList<>();
      List<Runnable> checks = new ArrayList<>();
      for (Map.Entry<String, Callable<Object>> operation : operations.entrySet()) {
        String what = operation.getKey();
        CountDownLatch frozen = proxy.beforeNextClientWriteContaining(proxy::freeze, writes.get(what));
        CompletableFuture<Object[]> outcome = new CompletableFuture<>();
        Thread thread = new Thread(() -> {
          Object result;
          try {
            result = operation.getValue().call();
          } catch (Throwable e) {
            result = e;
          }
          outcome.complete(new Object[] {result, System.nanoTime(), Thread.interrupted()});
        }, "fault-frozen-" + what);
        thread.start();
        boolean fired = frozen.await(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS);
        long interrupted = System.nanoTime();
        thread.interrupt();
        Object[] ended = outcome.get(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS);
        proxy.thaw();
        long took = (Long) ended[1] - interrupted;
        figures.add(what + " " + Figures.seconds(took) + " with " + describe(ended[0]));
        checks.add(() -> {
          assertTrue(fired, what + ": the proxy froze as it sent its command");
          assertTrue(ended[0] instanceof PrimeException && !(ended[0] instanceof CoreClosedException)
              && ((Throwable) ended[0]).getMessage().contains("interrupted"), what + ": fails with a PrimeException saying so: " + describe(ended[0]));
          assertTrue(took < Duration.ofSeconds(2).toNanos(), what + ": the interrupt ends the wait within about a second: " + Figures.seconds(took));
          assertEquals(Boolean.TRUE, ended[2], what + ": the flag is kept");
        });
      }
      String publishFailure = figures.get(0);
      ids.publish(3L);
      Optional<Long> after = Optional.empty();
      for (int i = 0; i < 3 && !after.equals(Optional.of(3L)); i++) after = reader.take(FaultMode.PATIENCE);
      List<?> deadLetters = core.deadLetters("ids-service");
      long missed = reader.missed();
      Figures.report("an interrupt of a publish or a read waiting on a frozen Redis, ended after it: " + String.join("; ", figures)
          + "; after the thaw a publish was read (" + after + "), deadLetters " + deadLetters.size() + ", missed " + missed);
      for (Runnable check : checks) check.run();
      assertTrue(publishFailure.contains("may not have been published"), "the publish says it may have been stored: " + publishFailure);
      assertTrue(figures.get(3).contains("may have cleared them"), "the clear says it may have cleared them: " + figures.get(3));
      assertEquals(Optional.of(3L), after, "a publish after the thaw is read");
      assertEquals(0, deadLetters.size(), "deadLetters works after the thaw");
      assertEquals(0L, missed, "missed() works after the thaw");
    }
  }

  private static String describe(Object outcome) {
    return outcome instanceof Throwable e ? e.getClass().getSimpleName() + " (" + e.getMessage() + ")" : "no exception: " + outcome;
  }
}

package dev.prime.internal;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.conformance.CapturedStderr;
import java.util.List;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.ExecutorService;
import java.util.concurrent.Executors;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicInteger;
import java.util.concurrent.atomic.AtomicLong;
import org.junit.jupiter.api.Test;

/** Bursts logged once in full, then counted in at most one summary line per interval. */
class RateLimitedLogTest {
  private static final long SECOND = 1_000_000_000L;
  private final AtomicLong clock = new AtomicLong(1_000 * SECOND);
  private final RateLimitedLog log =
      new RateLimitedLog(
          RateLimitedLogTest.class.getName(), 10 * SECOND, 10 * SECOND, clock::get);
  private final AtomicInteger firsts = new AtomicInteger();

  private List<String> summaries(CapturedStderr err, String key) {
    return err.lines().stream().filter(l -> l.contains(key + ": ")).toList();
  }

  @Test
  void aBurstIsLoggedInFullOnceThenSummarisedPerInterval() {
    try (CapturedStderr err = new CapturedStderr()) {
      for (int i = 0; i < 100; i++) { // 100 events in 0.99 s
        log.record("k1", 1, "event " + i, firsts::incrementAndGet);
        clock.addAndGet(SECOND / 100);
      }
      assertEquals(1, firsts.get());
      assertEquals(List.of(), summaries(err, "k1"), "no summary before the interval");
      clock.addAndGet(9 * SECOND);
      log.record("k1", 1, "event 100", firsts::incrementAndGet);
      List<String> lines = summaries(err, "k1");
      assertEquals(1, lines.size(), String.valueOf(lines));
      assertTrue(lines.get(0).contains("k1: 100 more in the last 10 s; the last: event 100"), lines.get(0));
      assertEquals(1, firsts.get());

      clock.addAndGet(11 * SECOND); // quiet: a new burst, logged in full again
      log.record("k1", 1, "again", firsts::incrementAndGet);
      assertEquals(2, firsts.get());
    }
  }

  @Test
  void theEndOfABurstIsSummarisedAtTheNextBurstOrAtFlush() {
    try (CapturedStderr err = new CapturedStderr()) {
      log.record("k2", 1, "a", firsts::incrementAndGet);
      log.record("k2", 5, "b", firsts::incrementAndGet);
      clock.addAndGet(30 * SECOND);
      log.record("k2", 1, "c", firsts::incrementAndGet);
      assertEquals(2, firsts.get());
      List<String> lines = summaries(err, "k2");
      assertEquals(1, lines.size(), String.valueOf(lines));
      assertTrue(lines.get(0).contains("k2: 5 more"), lines.get(0));

      log.record("k2", 3, "d", firsts::incrementAndGet);
      log.flush();
      log.flush(); // nothing owed any more
      lines = summaries(err, "k2");
      assertEquals(2, lines.size(), String.valueOf(lines));
      assertTrue(lines.get(1).contains("k2: 3 more"), lines.get(1));
    }
  }

  @Test
  void keysAreCountedApartAndThreadsLoseNoEvent() throws Exception {
    ExecutorService threads = Executors.newFixedThreadPool(4);
    CountDownLatch go = new CountDownLatch(1);
    try (CapturedStderr err = new CapturedStderr()) {
      for (int t = 0; t < 4; t++) {
        String key = "k3-" + (t % 2);
        threads.submit(
            () -> {
              go.await();
              for (int i = 0; i < 1_000; i++) {
                log.record(key, 1, "x", firsts::incrementAndGet);
              }
              return null;
            });
      }
      go.countDown();
      threads.shutdown();
      assertTrue(threads.awaitTermination(30, TimeUnit.SECONDS));
      log.flush();
      assertEquals(2, firsts.get(), "one first event per key");
      long counted =
          summaries(err, "k3-0").size() + summaries(err, "k3-1").size() == 2
              ? err.lines().stream()
                  .filter(l -> l.contains("k3-"))
                  .mapToLong(l -> Long.parseLong(l.replaceAll(".*: (\\d+) more.*", "$1")))
                  .sum()
              : -1;
      assertEquals(3_998, counted, "every event but the two firsts is counted, once");
    }
  }

  @Test
  void badPeriodsAreRefused() {
    assertThrows(
        IllegalArgumentException.class,
        () -> new RateLimitedLog(RateLimitedLogTest.class.getName(), 0, 1, clock::get));
  }
}

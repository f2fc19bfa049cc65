package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Source;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicInteger;
import org.junit.jupiter.api.Test;

/** Awkward conditions: tiny retention, slow readers, blocks that fail every other value. */
public interface AwkwardConformance extends ConformanceBase {

  @Test
  default void tinyRetentionWithASlowReaderLosesOnlyOldValuesAndCountsThem()
      throws InterruptedException {
    int n = 200;
    try (PrimeCore core = newCore(CoreConfig.builder().sourceRetention(2).build())) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source(events);
      Reader<Integer> slow = source.reader();
      core.start();
      List<Integer> seen = new ArrayList<>();
      for (int i = 0; i < n; i++) {
        events.publish(i);
        if (i % 10 == 9) {
          seen.add(takeOrFail(slow)); // the reader wakes up now and then and reads one value
        }
      }
      seen.addAll(slow.drain());
      for (int i = 1; i < seen.size(); i++) {
        assertTrue(seen.get(i - 1) < seen.get(i), "values stay in order: " + seen);
      }
      assertEquals(n - 1, seen.get(seen.size() - 1), "the newest value is never lost");
      assertEquals(n, seen.size() + slow.missed(), "every value is either seen or counted missed");
      assertTrue(slow.missed() > 0);
    }
  }

  @Test
  default void serviceFailingEveryOtherValueKeepsOrderForTheRest() throws InterruptedException {
    int n = 1000;
    AtomicInteger reported = new AtomicInteger();
    CountDownLatch allReported = new CountDownLatch(n / 2);
    CoreConfig config =
        CoreConfig.builder()
            .sourceRetention(n)
            .errorHandler(
                (service, input, error) -> {
                  reported.incrementAndGet();
                  allReported.countDown();
                })
            .build();
    try (PrimeCore core = newCore(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> out =
          core.link(
                  core.source(events),
                  core.chain(
                      (Integer x) -> {
                        if (x % 2 == 1) {
                          throw new IllegalArgumentException("odd " + x);
                        }
                        return x;
                      }))
              .reader();
      core.start();
      for (int i = 0; i < n; i++) {
        events.publish(i);
      }
      List<Integer> expected = new ArrayList<>();
      for (int i = 0; i < n; i += 2) {
        expected.add(i);
      }
      assertEquals(expected, takeOrFail(out, n / 2));
      assertTrue(allReported.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      assertEquals(n / 2, reported.get());
    }
  }

  @Test
  default void slowServiceBehindTinyRetentionSkipsToTheNewestValue()
      throws InterruptedException {
    CountDownLatch release = new CountDownLatch(1);
    CountDownLatch firstInside = new CountDownLatch(1);
    CountDownLatch newestDone = new CountDownLatch(1);
    List<Integer> processed = new java.util.concurrent.CopyOnWriteArrayList<>();
    try (PrimeCore core = newCore(CoreConfig.builder().sourceRetention(1).build())) {
      EventBlock<Integer> events = new EventBlock<>();
      core.link(
          core.source(events),
          core.chain(
              (Integer x) -> {
                processed.add(x);
                firstInside.countDown();
                try {
                  release.await();
                } catch (InterruptedException e) {
                  Thread.currentThread().interrupt();
                }
                if (x == 50) {
                  newestDone.countDown();
                }
                return x;
              }));
      core.start();
      events.publish(0);
      assertTrue(firstInside.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      for (int i = 1; i <= 50; i++) {
        events.publish(i);
      }
      release.countDown();
      assertTrue(newestDone.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      if (serviceInputIsAQueue()) {
        assertEquals(
            java.util.stream.IntStream.rangeClosed(0, 50).boxed().toList(),
            processed,
            "a service's input is a queue: nothing is skipped");
      } else {
        assertEquals(List.of(0, 50), processed, "the service skips to the newest retained value");
      }
    }
  }

  @Test
  default void manyChainsOnOneSource() throws InterruptedException {
    int chains = 8;
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source(events);
      List<Reader<Integer>> readers = new ArrayList<>();
      for (int c = 0; c < chains; c++) {
        int k = c;
        readers.add(core.link(source, core.chain((Integer x) -> x * 100 + k)).reader());
      }
      core.start();
      for (int i = 0; i < 20; i++) {
        events.publish(i);
      }
      for (int c = 0; c < chains; c++) {
        List<Integer> expected = new ArrayList<>();
        for (int i = 0; i < 20; i++) {
          expected.add(i * 100 + c);
        }
        assertEquals(expected, takeOrFail(readers.get(c), 20));
      }
    }
  }
}

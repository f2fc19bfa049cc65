package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreClosedException;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.PrimeException;
import dev.prime.QueueFullException;
import dev.prime.Reader;
import dev.prime.Source;
import java.time.Duration;
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

  /**
   * A service's input is a queue: a service slower than its publisher, behind a retention of one
   * value, still processes every value, in order; the publisher is held up meanwhile.
   */
  @Test
  default void slowServiceBehindTinyRetentionProcessesEveryValueInOrder()
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
      java.util.concurrent.atomic.AtomicReference<Throwable> publishFailure =
          new java.util.concurrent.atomic.AtomicReference<>();
      Thread publisher =
          new Thread(
              () -> {
                try {
                  for (int i = 1; i <= 50; i++) {
                    events.publish(i);
                  }
                } catch (Throwable e) {
                  publishFailure.set(e);
                }
              },
              "kit-slow-service-publisher");
      publisher.start();
      release.countDown();
      assertTrue(newestDone.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      publisher.join(patience().toMillis());
      assertEquals(null, publishFailure.get(), "no publish is refused while the service works");
      assertEquals(
          java.util.stream.IntStream.rangeClosed(0, 50).boxed().toList(),
          processed,
          "a service's input is a queue: nothing is skipped");
    }
  }

  /**
   * A publisher waiting for room in a stuck service's input honours interruption: it stops within
   * a second (not the publish timeout) with a {@link PrimeException} that says it was interrupted
   * (not a full queue, not a closed core), keeps the interrupt flag, and publishes nothing.
   */
  @Test
  default void anInterruptedPublisherWaitingForRoomStopsAtOnceAndPublishesNothing()
      throws InterruptedException {
    int capacity = 2;
    CountDownLatch release = new CountDownLatch(1);
    CountDownLatch firstInside = new CountDownLatch(1);
    CountDownLatch sentinelDone = new CountDownLatch(1);
    List<Integer> processed = new java.util.concurrent.CopyOnWriteArrayList<>();
    CoreConfig config = CoreConfig.builder().publishTimeout(Duration.ofSeconds(30)).build();
    try (PrimeCore core = newCoreWithServiceInputCapacity(config, capacity)) {
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
                if (x == -1) {
                  sentinelDone.countDown();
                }
                return x;
              }));
      core.start();
      events.publish(0);
      assertTrue(firstInside.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      for (int i = 1; i <= capacity; i++) {
        events.publish(i); // fills the stuck service's input
      }
      long began = System.nanoTime();
      Thread.currentThread().interrupt();
      try {
        PrimeException stopped = assertThrows(PrimeException.class, () -> events.publish(999));
        assertTrue(Thread.currentThread().isInterrupted(), "the interrupt flag is kept");
        assertFalse(stopped instanceof QueueFullException, "an interrupt is not a full queue: " + stopped);
        assertFalse(stopped instanceof CoreClosedException, "an interrupt is not a closed core: " + stopped);
        assertTrue(stopped.getMessage().contains("interrupted"), stopped.getMessage());
      } finally {
        Thread.interrupted();
      }
      Duration waited = Duration.ofNanos(System.nanoTime() - began);
      assertTrue(waited.compareTo(Duration.ofSeconds(1)) <= 0, "stopped within a second, took " + waited);
      release.countDown();
      events.publish(-1);
      assertTrue(sentinelDone.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      assertEquals(List.of(0, 1, 2, -1), processed, "the interrupted 999 reached nobody");
    }
  }

  /**
   * A stuck service holds its publishers up, and after the publish timeout refuses them with
   * {@link QueueFullException}: within the timeout and a second, and the refused value is
   * published to nobody (neither the service nor a plain reader ever sees it). Its message names
   * the source, the service and its capacity ({@link QueueFullException}), says that nothing was
   * published and how to fix it (among the fixes, a longer {@code publishTimeout}).
   */
  @Test
  default void stuckServiceMakesAPublishFailWithQueueFullWithinThePublishTimeout()
      throws InterruptedException {
    int capacity = 4;
    Duration timeout = Duration.ofMillis(300);
    CountDownLatch release = new CountDownLatch(1);
    CountDownLatch firstInside = new CountDownLatch(1);
    CountDownLatch sentinelDone = new CountDownLatch(1);
    List<Integer> processed = new java.util.concurrent.CopyOnWriteArrayList<>();
    CoreConfig config = CoreConfig.builder().publishTimeout(timeout).build();
    try (PrimeCore core = newCoreWithServiceInputCapacity(config, capacity)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source(events);
      core.link(
          source,
          core.chain(
              (Integer x) -> {
                processed.add(x);
                firstInside.countDown();
                try {
                  release.await();
                } catch (InterruptedException e) {
                  Thread.currentThread().interrupt();
                }
                if (x == -1) {
                  sentinelDone.countDown();
                }
                return x;
              }));
      try (Reader<Integer> watcher = source.reader()) {
        core.start();
        events.publish(0);
        assertTrue(firstInside.await(patience().toMillis(), TimeUnit.MILLISECONDS));
        for (int i = 1; i <= capacity; i++) {
          events.publish(i); // fills the stuck service's input
        }
        long began = System.nanoTime();
        QueueFullException refused =
            assertThrows(QueueFullException.class, () -> events.publish(999));
        Duration waited = Duration.ofNanos(System.nanoTime() - began);
        assertTrue(
            waited.compareTo(timeout.plusSeconds(1)) <= 0,
            "refused within the publish timeout and a second, took " + waited);
        assertTrue(
            waited.compareTo(timeout.minusMillis(20)) >= 0,
            "waited for room up to the publish timeout first, took " + waited);
        assertEquals(capacity, refused.capacity(), refused.getMessage());
        assertTrue(
            refused.serviceName() != null && !refused.serviceName().isBlank(),
            "names the service: " + refused.getMessage());
        for (String said :
            List.of(
                "'" + source.name() + "'",
                "'" + refused.serviceName() + "'",
                " " + capacity + " ",
                "nothing was published",
                "publishTimeout")) {
          assertTrue(
              refused.getMessage().contains(said),
              "names the source, the service and its capacity, says nothing was published and"
                  + " how to wait longer (" + said + "): " + refused.getMessage());
        }
        List<Integer> seen = watcher.drain(); // a plain reader may have missed the oldest
        assertEquals(capacity, seen.get(seen.size() - 1), "the newest value a reader sees: " + seen);
        release.countDown();
        events.publish(-1); // a sentinel, after room came
        assertTrue(sentinelDone.await(patience().toMillis(), TimeUnit.MILLISECONDS));
        assertEquals(List.of(0, 1, 2, 3, 4, -1), processed, "the refused 999 reached nobody");
        assertEquals(-1, takeOrFail(watcher), "the refused 999 was published to no reader");
      }
    }
  }

  /**
   * {@link CoreConfig.Builder#publishTimeout}: "zero (fail at once)". With a publish timeout of
   * zero, a publish that finds a service's input full waits for no room: it throws {@link
   * QueueFullException} within a second (the stuck service would hold it for the kit's whole
   * patience), naming the service as {@link PrimeCore#serviceNames()} does (of two chains linked
   * before they are linked to the source, the first, whose input is full), and publishes
   * nothing: the chains then process exactly the values that fitted, and a publish once there is
   * room goes through.
   */
  @Test
  default void aPublishTimeoutOfZeroRefusesAPublishToAFullInputAtOnce()
      throws InterruptedException {
    int capacity = 2;
    CountDownLatch inside = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    CountDownLatch sentinelDone = new CountDownLatch(1);
    List<Integer> processed = new java.util.concurrent.CopyOnWriteArrayList<>();
    CoreConfig config = CoreConfig.builder().publishTimeout(Duration.ZERO).build();
    try (PrimeCore core = newCoreWithServiceInputCapacity(config, capacity)) {
      EventBlock<Integer> events = new EventBlock<>();
      core.source(events)
          .then(
              stuckChain(core, "held", inside, release)
                  .then(
                      core.chain(
                          "after-held",
                          (Integer x) -> {
                            processed.add(x);
                            if (x == -1) {
                              sentinelDone.countDown();
                            }
                            return x;
                          })));
      core.start();
      try {
        fillStuckInput(events, inside, capacity);
        long began = System.nanoTime();
        QueueFullException refused =
            assertThrows(QueueFullException.class, () -> events.publish(99));
        Duration took = Duration.ofNanos(System.nanoTime() - began);
        assertTrue(took.compareTo(Duration.ofSeconds(1)) < 0, "refused at once, took " + took);
        assertEquals(
            "held", refused.serviceName(), "the chain whose input is full: " + refused.getMessage());
      } finally {
        release.countDown();
      }
      long deadline = System.nanoTime() + patience().toNanos();
      while (processed.size() < capacity + 1 && System.nanoTime() < deadline) {
        sentinelDone.await(1, TimeUnit.MILLISECONDS); // a bounded pause until room came
      }
      events.publish(-1); // a sentinel, once the input has room
      assertTrue(sentinelDone.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      assertEquals(List.of(0, 1, 2, -1), processed, "the refused 99 reached nobody");
    }
  }

  /**
   * A service that publishes into its own input waits for itself when that input is full: the
   * publish fails with {@link QueueFullException} after the publish timeout (never a hang), the
   * failure goes to the error handler, and the service goes on with the values that fitted.
   */
  @Test
  default void aServiceFeedingItsOwnFullInputFailsThatPublishInsteadOfHanging()
      throws InterruptedException {
    int capacity = 2;
    Duration timeout = Duration.ofMillis(200);
    java.util.concurrent.atomic.AtomicReference<Throwable> reported =
        new java.util.concurrent.atomic.AtomicReference<>();
    CountDownLatch failed = new CountDownLatch(1);
    CountDownLatch lastDone = new CountDownLatch(1);
    List<Integer> heard = new java.util.concurrent.CopyOnWriteArrayList<>();
    CoreConfig config =
        CoreConfig.builder()
            .publishTimeout(timeout)
            .errorHandler(
                (service, input, error) -> {
                  reported.compareAndSet(null, error);
                  failed.countDown();
                })
            .build();
    try (PrimeCore core = newCoreWithServiceInputCapacity(config, capacity)) {
      EventBlock<Integer> events = new EventBlock<>();
      core.source(events)
          .listen(
              (Integer x) -> {
                heard.add(x);
                if (x == 0) {
                  for (int i = 1; i <= capacity + 1; i++) {
                    events.publish(i); // the last finds its own input full
                  }
                }
                if (x == capacity) {
                  lastDone.countDown();
                }
              });
      core.start();
      long began = System.nanoTime();
      events.publish(0);
      assertTrue(failed.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      Duration took = Duration.ofNanos(System.nanoTime() - began);
      assertTrue(
          reported.get() instanceof QueueFullException,
          "the error handler got " + reported.get());
      assertTrue(
          took.compareTo(timeout.plusSeconds(1)) <= 0,
          "failed within the publish timeout and a second, took " + took);
      assertTrue(lastDone.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      assertEquals(List.of(0, 1, 2), heard, "the values that fitted, and not the refused one");
    }
  }

  /**
   * {@link QueueFullException}: "nothing of that publish was published", also where the full
   * service is one of several on the source: a publish refused because a stuck chain's input is
   * full reaches neither another chain linked to the same source, whose input has room, nor a
   * plain reader of the source; the values before and after it reach both, in order.
   */
  @Test
  default void aPublishRefusedForOneFullServiceReachesNoOtherServiceNorReader()
      throws InterruptedException {
    int capacity = 2;
    CountDownLatch inside = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    CoreConfig config = CoreConfig.builder().publishTimeout(Duration.ofMillis(200)).build();
    try (PrimeCore core = newCoreWithServiceInputCapacity(config, capacity)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("numbers", events);
      source.then(stuckChain(core, "held", inside, release));
      Reader<Integer> free = source.then(core.chain("free", (Integer x) -> x)).reader();
      Reader<Integer> plain = source.reader();
      core.start();
      try {
        events.publish(0);
        assertTrue(inside.await(patience().toMillis(), TimeUnit.MILLISECONDS), "0 is held");
        assertEquals(0, takeOrFail(free));
        assertEquals(0, takeOrFail(plain));
        for (int i = 1; i <= capacity; i++) {
          events.publish(i);
          assertEquals(i, takeOrFail(free), "the free chain keeps up");
          assertEquals(i, takeOrFail(plain), "the plain reader keeps up");
        }
        QueueFullException refused =
            assertThrows(QueueFullException.class, () -> events.publish(999));
        assertEquals("held", refused.serviceName(), refused.getMessage());
      } finally {
        release.countDown();
      }
      events.publish(-1); // a sentinel, once the held input has room
      assertEquals(-1, takeOrFail(free), "the refused 999 reached no other service");
      assertEquals(-1, takeOrFail(plain), "nor a plain reader");
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
  /**
   * A very large value travels like any other: a 4 MiB array published to a source reaches a
   * reader and a service whole, and a synchronous call takes and returns one whole (Optimus
   * carries values up to {@code OptimusCore.Builder.maxValueBytes}, 16 MiB by default, and
   * refuses a bigger one where it is given, at the publish or the call).
   */
  @Test
  default void aValueOfSeveralMebibytesTravelsWhole() throws InterruptedException {
    byte[] big = new byte[4 << 20];
    for (int i = 0; i < big.length; i++) {
      big[i] = (byte) (i * 31 + (i >>> 13));
    }
    try (PrimeCore core = newCore()) {
      EventBlock<byte[]> events = new EventBlock<>();
      Source<byte[]> source = core.source("big", events);
      Reader<byte[]> reader = source.reader();
      Reader<Integer> sums = source.then(core.chain("big-sum", AwkwardConformance::sum)).reader();
      dev.prime.Block<byte[], byte[]> reverse =
          core.chain(
                  "big-reverse",
                  (byte[] b) -> {
                    byte[] r = new byte[b.length];
                    for (int i = 0; i < b.length; i++) {
                      r[i] = b[b.length - 1 - i];
                    }
                    return r;
                  })
              .toBlock();
      core.start();
      events.publish(big);
      assertTrue(java.util.Arrays.equals(big, takeOrFail(reader)), "the reader got it whole");
      assertEquals(sum(big), takeOrFail(sums), "the service got it whole");
      byte[] reversed = reverse.process(big);
      assertEquals(big.length, reversed.length);
      assertEquals(big[0], reversed[reversed.length - 1]);
      assertEquals(sum(big), sum(reversed), "the call took and returned it whole");
    }
  }

  /** A checksum of every byte. */
  private static int sum(byte[] bytes) {
    int sum = 0;
    for (byte b : bytes) {
      sum = sum * 31 + b;
    }
    return sum;
  }

  /**
   * A wide fan-out keeps broadcast and delivery: 100 readers and 10 listeners of one source each
   * get every one of 100 values, in order.
   */
  @Test
  default void aWideFanOutGivesEveryReaderAndServiceEveryValueInOrder()
      throws InterruptedException {
    int values = 100;
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("wide", events);
      List<Reader<Integer>> readers = new ArrayList<>();
      for (int r = 0; r < 100; r++) {
        readers.add(source.reader());
      }
      List<List<Integer>> heard = new ArrayList<>();
      CountDownLatch allHeard = new CountDownLatch(10);
      for (int l = 0; l < 10; l++) {
        List<Integer> mine = new java.util.concurrent.CopyOnWriteArrayList<>();
        heard.add(mine);
        source.listen(
            x -> {
              mine.add(x);
              if (x == values - 1) {
                allHeard.countDown();
              }
            });
      }
      core.start();
      for (int i = 0; i < values; i++) {
        events.publish(i);
      }
      List<Integer> expected = java.util.stream.IntStream.range(0, values).boxed().toList();
      for (Reader<Integer> reader : readers) {
        assertEquals(expected, takeOrFail(reader, values));
      }
      assertTrue(allHeard.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      for (List<Integer> mine : heard) {
        assertEquals(expected, mine, "each listener heard every value, in order");
      }
    }
  }
}

package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.conformance.CapturedStderr;
import dev.prime.spi.GenericChainCompiler;
import java.time.Duration;
import java.util.ArrayList;
import java.util.List;
import java.util.Optional;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;

/** Ring and cursor arithmetic of the in-memory source, without running any service. */
class MemorySourceTest {

  /** The smallest core a MemorySource can belong to; its chains are never used here. */
  private static final class BareCore extends PrimeCore {
    BareCore() {
      this(CoreConfig.defaults());
    }

    BareCore(CoreConfig config) {
      super("bare", config);
    }

    @Override
    protected ChainCompiler<?> chainCompiler() {
      return new GenericChainCompiler();
    }
  }

  private static List<Integer> range(int from, int to) {
    List<Integer> values = new ArrayList<>();
    for (int i = from; i < to; i++) {
      values.add(i);
    }
    return values;
  }

  @Test
  void readerCreatedBeforePublishingSeesAllWithinRetention() {
    try (BareCore core = new BareCore()) {
      MemorySource<Integer> source = new MemorySource<>(core, "s", 4);
      Reader<Integer> reader = source.reader();
      range(0, 4).forEach(source::publish);
      assertEquals(range(0, 4), reader.drain());
      assertEquals(0, reader.missed());
    }
  }

  @Test
  void missesAreLoggedOnceAtWarnThenCounted() {
    List<String> warnings;
    try (CapturedStderr err = new CapturedStderr();
        BareCore core = new BareCore()) {
      MemorySource<Integer> source = new MemorySource<>(core, "lossy", 2);
      Reader<Integer> reader = source.reader();
      for (int lap = 0; lap < 100; lap++) { // 100 misses of 3 values each, in one burst
        range(0, 5).forEach(source::publish);
        reader.drain();
      }
      assertEquals(300, reader.missed());
      warnings =
          err.lines().stream()
              .filter(l -> l.contains("source 'lossy' of core '" + core.name() + "'"))
              .toList();
    }
    assertTrue(warnings.size() >= 1 && warnings.size() <= 3, String.join("\n", warnings));
    assertTrue(warnings.get(0).contains("WARN"), warnings.get(0));
    assertTrue(warnings.get(0).contains("missed 3 values"), warnings.get(0));
    assertTrue(warnings.get(0).contains("CoreConfig.sourceRetention"), warnings.get(0));
  }

  @Test
  void wrapAroundManyTimesKeepsTheNewestAndCountsMissed() {
    try (BareCore core = new BareCore()) {
      MemorySource<Integer> source = new MemorySource<>(core, "s", 3);
      Reader<Integer> reader = source.reader();
      range(0, 1000).forEach(source::publish);
      assertEquals(Optional.of(997), reader.poll());
      assertEquals(997, reader.missed());
      source.publish(1000);
      assertEquals(List.of(998, 999, 1000), reader.drain());
      assertEquals(997, reader.missed());
      Reader<Integer> late = source.reader();
      assertEquals(List.of(998, 999, 1000), late.drain());
      assertEquals(0, late.missed());
    }
  }

  /**
   * Slots are found by a mask when the retention is a power of two and by a remainder otherwise:
   * both keep every value, in order, lap after lap, for a plain reader and a service's batches.
   */
  @Test
  void everyRetentionWrapsInOrderWithMaskOrRemainder() throws InterruptedException {
    for (int retention : new int[] {1, 2, 3, 4, 5, 7, 8, 16, 1000, 1024}) {
      try (BareCore core = new BareCore()) {
        MemorySource<Integer> source = new MemorySource<>(core, "s", retention);
        Reader<Integer> reader = source.reader();
        @SuppressWarnings("unchecked")
        BatchReader<Integer> input = (BatchReader<Integer>) source.serviceInput("service");
        List<Integer> read = new ArrayList<>();
        List<Integer> batched = new ArrayList<>();
        int published = 0;
        for (int lap = 0; lap < 5; lap++) { // five laps of the ring, in bursts of the retention
          for (int i = 0; i < retention; i++) {
            source.publish(published++);
          }
          read.addAll(reader.drain());
          while (batched.size() < published) {
            input.takeAvailable(batched::add);
          }
        }
        assertEquals(range(0, published), read, "retention " + retention);
        assertEquals(range(0, published), batched, "retention " + retention);
        assertEquals(0, reader.missed(), "retention " + retention);
      }
    }
  }

  @Test
  void retentionOfOne() throws InterruptedException {
    try (BareCore core = new BareCore()) {
      MemorySource<String> source = new MemorySource<>(core, "s", 1);
      Reader<String> reader = source.reader();
      assertEquals(Optional.empty(), reader.take(Duration.ofMillis(1)));
      source.publish("a");
      source.publish("b");
      assertEquals("b", reader.take());
      assertEquals(1, reader.missed());
      assertEquals(Optional.empty(), reader.poll());
    }
  }

  @Test
  void readersAreIndependent() {
    try (BareCore core = new BareCore()) {
      MemorySource<Integer> source = new MemorySource<>(core, "s", 8);
      Reader<Integer> a = source.reader();
      Reader<Integer> b = source.reader();
      range(0, 5).forEach(source::publish);
      assertEquals(Optional.of(0), a.poll());
      assertEquals(range(0, 5), b.drain());
      assertEquals(range(1, 5), a.drain());
    }
  }

  @Test
  void badInputAndClose() {
    try (BareCore core = new BareCore()) {
      assertThrows(IllegalArgumentException.class, () -> new MemorySource<Integer>(core, "s", 0));
      MemorySource<Integer> source = new MemorySource<>(core, "s", 2);
      assertThrows(NullPointerException.class, () -> source.publish(null));
      Reader<Integer> reader = source.reader();
      source.publish(1);
      source.close();
      assertThrows(CoreClosedException.class, reader::poll);
      assertThrows(CoreClosedException.class, () -> source.publish(2));
      assertThrows(CoreClosedException.class, source::reader);
      assertTrue(source.toString().contains("s"));
    }
  }

  /**
   * Readers do not lock out the publisher, so a publisher racing through a tiny ring laps them
   * while they read: every reader must still see values in order, never a value from the wrong
   * lap, and account for every value as either seen or missed.
   */
  @Test
  void readersRacingAFastPublisherThroughATinyRingStayConsistent() throws Exception {
    int n = 200_000;
    try (BareCore core = new BareCore()) {
      MemorySource<Integer> source = new MemorySource<>(core, "s", 4);
      List<Reader<Integer>> readers = List.of(source.reader(), source.reader());
      java.util.concurrent.ExecutorService pool = java.util.concurrent.Executors.newFixedThreadPool(2);
      try {
        List<java.util.concurrent.Future<long[]>> results = new ArrayList<>();
        for (Reader<Integer> reader : readers) {
          results.add(
              pool.submit(
                  () -> {
                    long seen = 0;
                    int last = -1;
                    while (last < n - 1) {
                      Optional<Integer> next = reader.take(Duration.ofSeconds(20));
                      if (next.isEmpty()) {
                        throw new AssertionError("no value after " + last);
                      }
                      int value = next.get();
                      if (value <= last) {
                        throw new AssertionError(value + " after " + last);
                      }
                      last = value;
                      seen++;
                    }
                    return new long[] {seen, reader.missed()};
                  }));
        }
        for (int i = 0; i < n; i++) {
          source.publish(i);
        }
        for (java.util.concurrent.Future<long[]> result : results) {
          long[] counts = result.get(60, java.util.concurrent.TimeUnit.SECONDS);
          assertEquals(n, counts[0] + counts[1], "seen + missed");
        }
      } finally {
        pool.shutdownNow();
      }
    }
  }

  private static BareCore coreWaiting(Duration publishTimeout) {
    return new BareCore(CoreConfig.builder().publishTimeout(publishTimeout).build());
  }

  @Test
  void aServiceInputIsNeverLappedAndAFullOneRefusesThePublishAfterTheTimeout() {
    try (BareCore core = coreWaiting(Duration.ofMillis(100))) {
      MemorySource<Integer> source = new MemorySource<>(core, "s", 3);
      Reader<Integer> input = source.serviceInput("svc");
      Reader<Integer> plain = source.reader();
      range(0, 3).forEach(source::publish);
      long began = System.nanoTime();
      QueueFullException full = assertThrows(QueueFullException.class, () -> source.publish(3));
      long waitedMillis = (System.nanoTime() - began) / 1_000_000;
      assertTrue(waitedMillis >= 90 && waitedMillis < 1_100, "waited " + waitedMillis + " ms");
      assertEquals("svc", full.serviceName());
      assertEquals(3, full.capacity());
      assertTrue(full.getMessage().contains("'s'"), full.getMessage());
      assertTrue(full.getMessage().contains("sourceRetention"), full.getMessage());
      assertEquals(Optional.of(0), input.poll()); // room for one
      source.publish(4);
      assertEquals(List.of(1, 2, 4), input.drain(), "the refused 3 was published to nobody");
      assertEquals(List.of(1, 2, 4), plain.drain(), "a plain reader is lapped as before");
      assertEquals(1, plain.missed());
      assertEquals(0, input.missed());
    }
  }

  @Test
  void anInterruptedPublisherWaitingForRoomStopsAtOnceAndPublishesNothing() {
    try (BareCore core = coreWaiting(Duration.ofSeconds(30))) {
      MemorySource<Integer> source = new MemorySource<>(core, "s", 2);
      Reader<Integer> input = source.serviceInput("svc");
      range(0, 2).forEach(source::publish);
      Thread.currentThread().interrupt();
      long began = System.nanoTime();
      try {
        PrimeException stopped = assertThrows(PrimeException.class, () -> source.publish(2));
        assertTrue(Thread.currentThread().isInterrupted(), "the interrupt flag is kept");
        assertTrue(stopped.getMessage().contains("interrupted"), stopped.getMessage());
        assertTrue(!(stopped instanceof QueueFullException), "an interrupt is not a full queue");
      } finally {
        Thread.interrupted();
      }
      long waitedMillis = (System.nanoTime() - began) / 1_000_000;
      assertTrue(waitedMillis < 1_000, "waited " + waitedMillis + " ms of a 30 s publish timeout");
      assertEquals(List.of(0, 1), input.drain(), "the interrupted publish stored nothing");
    }
  }

  @Test
  void plainReadersNeverHoldPublishersUp() {
    try (BareCore core = coreWaiting(Duration.ZERO)) {
      MemorySource<Integer> source = new MemorySource<>(core, "s", 2);
      Reader<Integer> plain = source.reader();
      Reader<Integer> collector = source.serviceReader();
      range(0, 100).forEach(source::publish);
      assertEquals(List.of(98, 99), plain.drain());
      assertEquals(98, plain.missed());
      assertEquals(List.of(98, 99), collector.drain());
    }
  }

  @Test
  void aClosedServiceInputStopsGating() {
    try (BareCore core = coreWaiting(Duration.ZERO)) {
      MemorySource<Integer> source = new MemorySource<>(core, "s", 2);
      Reader<Integer> stopped = source.serviceInput("stopped");
      Reader<Integer> running = source.serviceInput("running");
      range(0, 2).forEach(source::publish);
      assertThrows(QueueFullException.class, () -> source.publish(2));
      assertEquals(List.of(0, 1), running.drain());
      QueueFullException full = assertThrows(QueueFullException.class, () -> source.publish(2));
      assertEquals("stopped", full.serviceName(), "the input furthest behind is named");
      stopped.close();
      for (int i = 2; i < 10; i++) {
        source.publish(i); // would be refused if the closed input still gated
        assertEquals(Optional.of(i), running.poll());
      }
      assertEquals(0, running.missed());
    }
  }

  @Test
  void aPublisherKeepsPaceWithAServiceThroughATinyInput() throws Exception {
    int n = 20_000;
    try (BareCore core = coreWaiting(Duration.ofSeconds(30))) {
      MemorySource<Integer> source = new MemorySource<>(core, "s", 2);
      Reader<Integer> input = source.serviceInput("svc");
      java.util.concurrent.ExecutorService pool =
          java.util.concurrent.Executors.newSingleThreadExecutor();
      try {
        java.util.concurrent.Future<List<Integer>> taken =
            pool.submit(
                () -> {
                  List<Integer> values = new ArrayList<>();
                  for (int i = 0; i < n; i++) {
                    values.add(input.take());
                  }
                  return values;
                });
        range(0, n).forEach(source::publish);
        assertEquals(range(0, n), taken.get(60, java.util.concurrent.TimeUnit.SECONDS));
        assertEquals(0, input.missed());
      } finally {
        pool.shutdownNow();
      }
    }
  }

  @Test
  void closingTheSourceWakesAWaitingPublisher() throws Exception {
    try (BareCore core = coreWaiting(Duration.ofSeconds(30))) {
      MemorySource<Integer> source = new MemorySource<>(core, "s", 1);
      source.serviceInput("svc");
      source.publish(0);
      java.util.concurrent.CompletableFuture<Throwable> failure =
          java.util.concurrent.CompletableFuture.supplyAsync(
              () -> {
                try {
                  source.publish(1);
                  return null;
                } catch (Throwable e) {
                  return e;
                }
              });
      // the publisher is (or soon will be) waiting for room; closing must wake it
      source.close();
      Throwable thrown = failure.get(5, java.util.concurrent.TimeUnit.SECONDS);
      assertTrue(thrown instanceof CoreClosedException, String.valueOf(thrown));
    }
  }

  @Test
  void waitingBudgetsAreCheckedAndAReaderWithoutOneIsWokenByAPublish() throws Exception {
    try (BareCore core = new BareCore()) {
      IllegalArgumentException negative =
          assertThrows(
              IllegalArgumentException.class,
              () -> new MemorySource<Integer>(core, "s", 2, null, () -> {}, -1, 0));
      assertTrue(negative.getMessage().contains("spinNanos"), negative.getMessage());
      assertThrows(
          IllegalArgumentException.class,
          () -> new MemorySource<Integer>(core, "s", 2, null, () -> {}, 10, 5));

      // no spin, no yield: the reader parks at once, and only the publish can wake it
      MemorySource<Integer> source = new MemorySource<>(core, "s", 2, null, () -> {}, 0, 0);
      Reader<Integer> reader = source.reader();
      CompletableFuture<Integer> taken = new CompletableFuture<>();
      Thread taker =
          new Thread(
              () -> {
                try {
                  taken.complete(reader.take());
                } catch (Throwable e) {
                  taken.completeExceptionally(e);
                }
              });
      taker.start();
      long deadline = System.nanoTime() + Duration.ofSeconds(10).toNanos();
      while (taker.getState() != Thread.State.WAITING && System.nanoTime() < deadline) {
        Thread.onSpinWait(); // bounded: until the taker parks, at most 10 s
      }
      assertEquals(Thread.State.WAITING, taker.getState(), "the reader parked at once");
      source.publish(7);
      assertEquals(7, taken.get(10, TimeUnit.SECONDS));
      taker.join(10_000);
    }
  }

  /** Waits (bounded) until {@code source} has {@code expected} announced readers. */
  private static void awaitAnnounced(MemorySource<?> source, int expected) {
    long deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(10);
    while (source.announcedReaders() != expected) {
      assertTrue(
          System.nanoTime() - deadline < 0,
          "announced readers stayed " + source.announcedReaders() + ", expected " + expected);
      java.util.concurrent.locks.LockSupport.parkNanos(100_000);
    }
  }

  @Test
  void aTakeThatParkedAnnouncesItselfAndWithdrawsWhenAValueComes() throws Exception {
    try (BareCore core = new BareCore()) {
      MemorySource<Integer> source = new MemorySource<>(core, "s", 4);
      Reader<Integer> reader = source.reader();
      CompletableFuture<Integer> taken = new CompletableFuture<>();
      Thread taker = new Thread(() -> {
        try {
          taken.complete(reader.take());
        } catch (Throwable e) {
          taken.completeExceptionally(e);
        }
      });
      taker.start();
      awaitAnnounced(source, 1); // past its spin and yield: publishers now look for sleepers
      source.publish(7);
      assertEquals(7, taken.get(10, TimeUnit.SECONDS));
      taker.join(10_000);
      assertEquals(0, source.announcedReaders(), "the take ended: publishers need not fence");
    }
  }

  @Test
  void anExpiredOrInterruptedTakeWithdrawsItsAnnouncement() throws Exception {
    try (BareCore core = new BareCore()) {
      MemorySource<Integer> source = new MemorySource<>(core, "s", 4);
      Reader<Integer> reader = source.reader();
      assertEquals(Optional.empty(), reader.take(Duration.ofMillis(20)));
      assertEquals(0, source.announcedReaders());

      CompletableFuture<Throwable> failure = new CompletableFuture<>();
      Thread taker = new Thread(() -> {
        try {
          reader.take();
          failure.complete(null);
        } catch (Throwable e) {
          failure.complete(e);
        }
      });
      taker.start();
      awaitAnnounced(source, 1);
      taker.interrupt();
      assertTrue(failure.get(10, TimeUnit.SECONDS) instanceof InterruptedException);
      taker.join(10_000);
      assertEquals(0, source.announcedReaders());
    }
  }

  @Test
  @SuppressWarnings("unchecked") // a service input is a MemoryReader, which is a BatchReader
  void aServiceInputThatParkedWithdrawsItsAnnouncementBeforeItRunsTheValues() throws Exception {
    try (BareCore core = new BareCore()) {
      MemorySource<Integer> source = new MemorySource<>(core, "s", 4);
      BatchReader<Integer> input = (BatchReader<Integer>) source.serviceInput("svc");
      CompletableFuture<Integer> announcedWhileRunning = new CompletableFuture<>();
      Thread service = new Thread(() -> {
        try {
          input.takeAvailable(value -> {
            announcedWhileRunning.complete(source.announcedReaders());
            return true;
          });
        } catch (Throwable e) {
          announcedWhileRunning.completeExceptionally(e);
        }
      });
      service.start();
      awaitAnnounced(source, 1);
      source.publish(1);
      assertEquals(0, announcedWhileRunning.get(10, TimeUnit.SECONDS),
          "a service running its values is not parking: its publishers must not fence");
      service.join(10_000);
      assertEquals(0, source.announcedReaders());
    }
  }
}

package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNotEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Source;
import java.time.Duration;
import java.util.List;
import java.util.Optional;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.ExecutionException;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.function.Executable;

/** Sources and readers: broadcast, retention, late readers and the take/poll/drain contract. */
public interface SourceConformance extends ConformanceBase {

  @Test
  default void everyReaderSeesEveryValueInOrder() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<String> events = new EventBlock<>();
      Source<String> source = core.source("words", events);
      assertEquals("words", source.name());
      assertEquals(core, source.core());
      Reader<String> r1 = source.reader();
      Reader<String> r2 = source.reader();
      Reader<String> r3 = source.reader();
      core.start();
      List<String> words = List.of("a", "b", "c", "d");
      words.forEach(events::publish);
      assertEquals(words, takeOrFail(r1, 4));
      assertEquals(words, takeOrFail(r2, 4));
      assertEquals(words, r3.drain());
    }
  }

  @Test
  default void lateReaderSeesRetainedValues() throws InterruptedException {
    try (PrimeCore core = newCore(CoreConfig.builder().sourceRetention(3).build())) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source(events);
      core.start();
      for (int i = 1; i <= 5; i++) {
        events.publish(i);
      }
      Reader<Integer> late = source.reader();
      assertEquals(List.of(3, 4, 5), late.drain());
      assertEquals(0, late.missed());
      events.publish(6);
      assertEquals(6, takeOrFail(late));
    }
  }

  @Test
  default void readerThatFallsBehindCountsMissedValues() throws InterruptedException {
    try (PrimeCore core = newCore(CoreConfig.builder().sourceRetention(4).build())) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source(events);
      Reader<Integer> slow = source.reader();
      core.start();
      for (int i = 1; i <= 10; i++) {
        events.publish(i);
      }
      assertEquals(List.of(7, 8, 9, 10), slow.drain());
      assertEquals(6, slow.missed());
    }
  }

  @Test
  default void takeBlocksUntilAValueIsPublished() throws Exception {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> reader = core.source(events).reader();
      core.start();
      CountDownLatch waiting = new CountDownLatch(1);
      CompletableFuture<Integer> taken =
          CompletableFuture.supplyAsync(
              () -> {
                waiting.countDown();
                try {
                  return reader.take();
                } catch (InterruptedException e) {
                  Thread.currentThread().interrupt();
                  throw new IllegalStateException(e);
                }
              });
      assertTrue(waiting.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      assertTrue(!taken.isDone(), "take() returned before any value was published");
      events.publish(7);
      assertEquals(7, taken.get(patience().toMillis(), TimeUnit.MILLISECONDS));
    }
  }

  @Test
  default void takeWithTimeoutPollAndDrain() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> reader = core.source(events).reader();
      core.start();
      assertEquals(Optional.empty(), reader.take(Duration.ofMillis(20)));
      assertEquals(Optional.empty(), reader.take(Duration.ZERO));
      assertEquals(Optional.empty(), reader.take(Duration.ofMillis(-5)));
      assertEquals(Optional.empty(), reader.poll());
      assertEquals(List.of(), reader.drain());
      events.publish(1);
      events.publish(2);
      events.publish(3);
      assertEquals(Optional.of(1), reader.take(patience()));
      assertEquals(Optional.of(2), reader.poll());
      assertEquals(List.of(3), reader.drain());
      assertEquals(List.of(), reader.drain());
      assertEquals(Optional.empty(), reader.poll());
      assertThrows(NullPointerException.class, () -> reader.take(null));
    }
  }

  @Test
  default void aClosedReaderFailsEveryLaterCallAndWakesItsWaiters() throws Exception {
    Reader<Integer> kept;
    Reader<Integer> closing;
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source(events);
      kept = source.reader();
      closing = source.reader();
      core.start();
      events.publish(1);
      assertEquals(1, takeOrFail(closing));
      CountDownLatch waiting = new CountDownLatch(1);
      CompletableFuture<Integer> blocked =
          CompletableFuture.supplyAsync(
              () -> {
                waiting.countDown();
                try {
                  return closing.take();
                } catch (InterruptedException e) {
                  Thread.currentThread().interrupt();
                  throw new IllegalStateException("interrupted", e);
                }
              });
      assertTrue(waiting.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      long started = System.nanoTime();
      closing.close();
      closing.close(); // idempotent
      ExecutionException woken =
          assertThrows(
              ExecutionException.class,
              () -> blocked.get(patience().toMillis(), TimeUnit.MILLISECONDS));
      assertTrue(
          woken.getCause() instanceof IllegalStateException
              && woken.getCause().getMessage().contains("reader closed"),
          "a take blocked at close() ends with IllegalStateException: " + woken.getCause());
      Duration wakeTook = Duration.ofNanos(System.nanoTime() - started);
      assertTrue(wakeTook.compareTo(Duration.ofSeconds(3)) < 0, "woken after " + wakeTook);
      List<Executable> calls =
          List.of(
              closing::take,
              () -> closing.take(Duration.ofMillis(10)),
              closing::poll,
              closing::drain,
              closing::missed);
      for (Executable call : calls) {
        IllegalStateException e = assertThrows(IllegalStateException.class, call);
        assertTrue(e.getMessage().contains("reader closed"), e.getMessage());
      }
      events.publish(2);
      assertEquals(List.of(1, 2), List.of(takeOrFail(kept), takeOrFail(kept)), "others read on");
    }
    kept.close(); // on a closed core too: no exception
    closing.close();
  }

  @Test
  default void sourcesCarryNoNulls() {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      core.source(events);
      core.start();
      assertThrows(NullPointerException.class, () -> events.publish(null));
    }
  }

  @Test
  default void oneEventBlockFeedsSeveralSourcesAndCores() throws InterruptedException {
    EventBlock<Integer> events = new EventBlock<>();
    try (PrimeCore a = newCore();
        PrimeCore b = newCore()) {
      assertNotEquals(a.name(), b.name());
      Reader<Integer> ra = a.source(events).reader();
      Reader<Integer> rb = b.source(events).reader();
      a.start();
      b.start();
      events.publish(5);
      assertEquals(5, takeOrFail(ra));
      assertEquals(5, takeOrFail(rb));
    }
  }

  @Test
  default void filterFlatMapAndListen() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source(events);
      Reader<Integer> odd = source.filter(x -> x % 2 == 1).reader();
      Reader<Integer> twice = source.flatMap(x -> List.of(x, x)).reader();
      CopyOnWriteArrayList<Integer> heard = new CopyOnWriteArrayList<>();
      CountDownLatch allHeard = new CountDownLatch(3);
      source.listen(
          x -> {
            heard.add(x);
            allHeard.countDown();
          });
      core.start();
      events.publish(1);
      events.publish(2);
      events.publish(3);
      assertEquals(List.of(1, 3), takeOrFail(odd, 2));
      assertEquals(List.of(1, 1, 2, 2, 3, 3), takeOrFail(twice, 6));
      assertTrue(allHeard.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      assertEquals(List.of(1, 2, 3), heard);
    }
  }
}

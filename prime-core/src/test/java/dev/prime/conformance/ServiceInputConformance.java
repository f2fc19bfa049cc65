package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.QueueFullException;
import dev.prime.Source;
import java.time.Duration;
import java.util.List;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.function.IntPredicate;
import org.junit.jupiter.api.Test;

/**
 * The input of every kind of service is a queue (architecture, <i>Sources, readers and
 * retention</i>: "The input of a service (a chain linked to a source, a filter, a flat-map, a
 * listener) is not a window but a queue, on every media"), checked here for the filter, the
 * flat-map and the listener ({@link AwkwardConformance} checks a chain's).
 */
public interface ServiceInputConformance extends ConformanceBase {

  /**
   * A stuck filter, flat-map or listener holds its publisher when its input is full, and after
   * {@link CoreConfig#publishTimeout()} the publish fails with {@link QueueFullException} naming
   * that service as the topology names it ({@code filter(numbers)}, {@code flatMap(numbers)},
   * {@code listen(numbers)}) and its capacity; the refused value reaches nobody, and once the
   * service goes on it gets every value its input accepted, in order, none missed.
   */
  @Test
  default void aStuckFilterFlatMapOrListenerHoldsThePublisherAndMissesNothing()
      throws InterruptedException {
    for (String kind : List.of("filter", "flatMap", "listen")) {
      int capacity = 4;
      Duration timeout = Duration.ofMillis(300);
      CountDownLatch release = new CountDownLatch(1);
      CountDownLatch firstInside = new CountDownLatch(1);
      CountDownLatch sentinelDone = new CountDownLatch(1);
      List<Integer> processed = new CopyOnWriteArrayList<>();
      IntPredicate stuck =
          x -> {
            processed.add(x);
            firstInside.countDown();
            try {
              release.await(patience().toMillis(), TimeUnit.MILLISECONDS);
            } catch (InterruptedException e) {
              Thread.currentThread().interrupt();
            }
            if (x == -1) {
              sentinelDone.countDown();
            }
            return true;
          };
      CoreConfig config = CoreConfig.builder().publishTimeout(timeout).build();
      try (PrimeCore core = newCoreWithServiceInputCapacity(config, capacity)) {
        EventBlock<Integer> events = new EventBlock<>();
        Source<Integer> source = core.source("numbers", events);
        switch (kind) {
          case "filter" -> source.filter(stuck::test);
          case "flatMap" -> source.flatMap(x -> stuck.test(x) ? List.of(x) : List.<Integer>of());
          default -> source.listen(stuck::test);
        }
        String service = kind + "(numbers)";
        assertEquals(List.of(service), List.copyOf(core.serviceNames()), kind);
        core.start();
        events.publish(0);
        assertTrue(
            firstInside.await(patience().toMillis(), TimeUnit.MILLISECONDS),
            kind + ": 0 reached the service");
        for (int i = 1; i <= capacity; i++) {
          events.publish(i); // fills the stuck service's input
        }
        long began = System.nanoTime();
        QueueFullException refused =
            assertThrows(QueueFullException.class, () -> events.publish(999), kind);
        Duration waited = Duration.ofNanos(System.nanoTime() - began);
        assertTrue(
            waited.compareTo(timeout.plusSeconds(1)) <= 0,
            kind + ": refused within the publish timeout and a second, took " + waited);
        assertEquals(service, refused.serviceName(), kind + ": " + refused.getMessage());
        assertEquals(capacity, refused.capacity(), kind + ": " + refused.getMessage());
        assertTrue(
            refused.getMessage().contains("'" + service + "'"),
            kind + ": the message names the service: " + refused.getMessage());
        release.countDown();
        events.publish(-1); // a sentinel, after room came
        assertTrue(
            sentinelDone.await(patience().toMillis(), TimeUnit.MILLISECONDS),
            kind + ": the sentinel was processed");
        assertEquals(
            List.of(0, 1, 2, 3, 4, -1), processed, kind + ": every accepted value, the refused 999 none");
      }
    }
  }
}

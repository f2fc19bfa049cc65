package dev.prime.bench;

import static org.junit.jupiter.api.Assertions.assertEquals;

import java.util.concurrent.CompletableFuture;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.Timeout;

/** The hand-off benchmarks' completion counter, with a real consumer thread. */
class ArrivalsTest {

  @Test
  @Timeout(value = 30, unit = TimeUnit.SECONDS)
  void awaitReturnsOnceTheConsumerReportedTheBatchWithItsSum() throws Exception {
    Arrivals arrivals = new Arrivals();
    CountDownLatch start = new CountDownLatch(1);
    CompletableFuture<Void> consumer =
        CompletableFuture.runAsync(
            () -> {
              try {
                start.await();
              } catch (InterruptedException e) {
                Thread.currentThread().interrupt();
                return;
              }
              for (int i = 1; i <= 10_000; i++) {
                arrivals.arrive(i);
              }
            });
    start.countDown();
    long sum = arrivals.await(10_000);
    assertEquals(10_000L * 10_001 / 2, sum);
    assertEquals(10_000, arrivals.count());
    consumer.get(10, TimeUnit.SECONDS);
  }

  @Test
  void awaitReturnsAtOnceWhenTheTargetIsAlreadyReached() {
    Arrivals arrivals = new Arrivals();
    arrivals.arrive(5);
    arrivals.arrive(7);
    assertEquals(12, arrivals.await(2));
    assertEquals(12, arrivals.await(1));
  }
}

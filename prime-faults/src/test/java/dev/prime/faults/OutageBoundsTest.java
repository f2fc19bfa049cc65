package dev.prime.faults;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.EventBlock;
import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.optimus.OptimusCore;
import java.time.Duration;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.Callable;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.ExecutorService;
import java.util.concurrent.Executors;
import java.util.concurrent.Future;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.TimeoutException;
import org.junit.jupiter.api.Test;

/**
 * Issue 9 item 7: with redis-server killed and not restarted, every operation that has a bound
 * honours it within the bound + 1 s: {@code EventBlock.publish} (the publish timeout, 10 s by
 * default), a call with a 3 s call timeout, {@code take(2 s)}, and {@code poll()} (never waits for
 * the network), each giving up with {@code RedisUnavailableException}. All four run at once; then
 * {@code close()} ends within its shutdown timeout.
 */
class OutageBoundsTest {
  private static final Duration PUBLISH_TIMEOUT = Duration.ofSeconds(10);
  private static final Duration CALL_TIMEOUT = Duration.ofSeconds(3);
  private static final Duration TAKE_TIMEOUT = Duration.ofSeconds(2);
  private static final Duration SLACK = Duration.ofSeconds(1);

  private record Bound(String what, Duration limit, Callable<String> operation) {}

  private record Result(String what, Duration limit, long nanos, String outcome) {
    boolean inBound() {
      return nanos >= 0 && nanos <= limit.plus(SLACK).toNanos();
    }

    @Override
    public String toString() {
      return what + " " + (nanos < 0 ? "still blocked" : Figures.seconds(nanos)) + " (bound " + Figures.seconds(limit) + ", " + outcome + ")";
    }
  }

  @Test
  void everyBoundedOperationEndsWithinItsBoundWhileRedisIsDown() throws Exception {
    ExecutorService pool = Executors.newFixedThreadPool(4);
    RedisProcess redis = RedisProcess.start(RedisProcess.Persistence.NONE, null);
    OptimusCore core = Cores.builder(redis.url(), "outage", 1024, null).callTimeout(CALL_TIMEOUT).build();
    try {
      EventBlock<Long> numbers = new EventBlock<>();
      Source<Long> output = core.source("numbers", numbers).then(core.<Long, Long>chain("inc", x -> x + 1));
      Reader<Long> reader = output.reader();
      Reader<Long> polled = output.reader(); // its own reader: take() holds the other one
      Block<Long, Long> echo = core.<Long, Long>chain("echo", x -> x).toBlock();
      core.start();
      numbers.publish(1L);
      assertTrue(reader.take(Duration.ofSeconds(10)).isPresent(), "a value before the outage");
      assertTrue(polled.take(Duration.ofSeconds(10)).isPresent(), "the other reader has it too (and nothing buffered now)");
      assertTrue(echo.process(5L) == 5L, "a call before the outage");

      redis.kill();
      List<Bound> bounds = List.of(
          new Bound("publish", PUBLISH_TIMEOUT, () -> {
            numbers.publish(2L);
            return "returned";
          }),
          new Bound("call", CALL_TIMEOUT, () -> "returned " + echo.process(6L)),
          new Bound("take(2 s)", TAKE_TIMEOUT, () -> "returned " + reader.take(TAKE_TIMEOUT)),
          new Bound("poll", Duration.ZERO, () -> "returned " + polled.poll()));
      CountDownLatch go = new CountDownLatch(1);
      List<Future<Result>> futures = new ArrayList<>();
      for (Bound bound : bounds) {
        futures.add(pool.submit(() -> {
          go.await();
          long started = System.nanoTime();
          String outcome;
          try {
            outcome = bound.operation().call();
          } catch (Exception e) {
            outcome = "threw " + e.getClass().getSimpleName();
          }
          return new Result(bound.what(), bound.limit(), System.nanoTime() - started, outcome);
        }));
      }
      go.countDown();
      long deadline = System.nanoTime() + PUBLISH_TIMEOUT.plus(SLACK).plusSeconds(2).toNanos();
      List<Result> results = new ArrayList<>();
      for (int i = 0; i < bounds.size(); i++) {
        try {
          results.add(futures.get(i).get(Math.max(1, deadline - System.nanoTime()), TimeUnit.NANOSECONDS));
        } catch (TimeoutException e) {
          results.add(new Result(bounds.get(i).what(), bounds.get(i).limit(), -1, "no answer"));
        }
      }
      long closeStarted = System.nanoTime();
      core.close();
      long closeTook = System.nanoTime() - closeStarted;
      Figures.report("Redis down: " + results + "; close() " + Figures.seconds(closeTook));
      for (Result result : results) assertTrue(result.inBound(), "ends within its bound + 1 s: " + result);
      for (Result result : results) {
        assertEquals("threw RedisUnavailableException", result.outcome(), "gives up with RedisUnavailableException: " + result);
      }
      Duration shutdown = core.config().shutdownTimeout().plus(SLACK);
      assertTrue(closeTook <= shutdown.toNanos(), "close() while Redis is down took " + Figures.seconds(closeTook));
    } finally {
      core.close();
      pool.shutdownNow();
      pool.awaitTermination(10, TimeUnit.SECONDS);
      redis.close();
    }
  }
}

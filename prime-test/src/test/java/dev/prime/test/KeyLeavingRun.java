package dev.prime.test;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import java.net.URI;
import java.time.Duration;
import java.util.List;
import redis.clients.jedis.Jedis;

/**
 * A run on Optimus that leaves Redis keys behind until they are deleted: a source, a chain that
 * dead-letters one value, a reader; for the tests that the extension deletes a run's keys.
 */
final class KeyLeavingRun {
  private KeyLeavingRun() {}

  /**
   * Runs the topology on {@code core}.
   *
   * @param core the run's core, not started
   * @param url the Redis the core's keys are in
   * @return the core's name and how many keys it had in that Redis, separated by a space
   * @throws InterruptedException if interrupted while reading
   */
  static String run(PrimeCore core, String url) throws InterruptedException {
    EventBlock<Integer> numbers = new EventBlock<>();
    Reader<Integer> out =
        core.source("numbers", numbers)
            .then(core.chain("not-two", (Integer x) -> {
              if (x == 2) {
                throw new IllegalArgumentException("two");
              }
              return x;
            }))
            .reader();
    core.start();
    numbers.publish(1);
    numbers.publish(2);
    numbers.publish(3);
    assertEquals(1, out.take(Duration.ofSeconds(20)).orElseThrow());
    assertEquals(3, out.take(Duration.ofSeconds(20)).orElseThrow());
    return core.name() + " " + keysOf(url, core.name()).size();
  }

  /**
   * Asserts that each run of {@code log} (lines {@link #run} returned) had keys in the Redis at
   * {@code url} while it ran, at least 5, and that none of {@code cores}' keys is left there.
   */
  static void assertEveryRunHadKeysAndLeftNone(List<String> log, List<PrimeCore> cores, String url) {
    for (String line : log) {
      int during = Integer.parseInt(line.substring(line.indexOf(' ') + 1));
      assertTrue(during >= 5, "the run had keys in the Redis at " + url + ": " + line);
    }
    for (PrimeCore core : cores) {
      assertEquals(List.of(), keysOf(url, core.name()), "keys of " + core.name() + " after its run");
    }
  }

  /** {@return the keys of {@code topology} in the Redis at {@code url}} */
  static List<String> keysOf(String url, String topology) {
    try (Jedis jedis = new Jedis(URI.create(url))) {
      return List.copyOf(jedis.keys("prime:{" + topology + "}:*"));
    }
  }
}

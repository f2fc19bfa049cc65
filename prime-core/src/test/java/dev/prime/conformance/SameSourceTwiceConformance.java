package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;

import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.Tuple2;
import java.util.ArrayList;
import java.util.List;
import java.util.Optional;
import org.junit.jupiter.api.Test;

/**
 * A combinator given one source twice treats it as two inputs, each of which takes every value
 * (architecture, <i>Combinators, timers and the clock</i>: {@code zip} pairs "the n-th value of
 * every source", {@code merge} emits "every value of every source").
 */
public interface SameSourceTwiceConformance extends ConformanceBase {

  /**
   * {@code zip(a, a)} pairs each value with itself, {@code merge(a, a)} emits each value twice and
   * {@code a.withLatestFrom(a)} pairs each value with the latest value of {@code a}.
   */
  @Test
  default void aCombinatorGivenOneSourceTwiceTakesEveryValueOnEachInput() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> a = core.source("a", events);
      Reader<Tuple2<Integer, Integer>> zipped = core.zip(a, a).reader();
      Reader<Integer> merged = core.merge(a, a).reader();
      core.start();
      for (int i = 1; i <= 5; i++) {
        events.publish(i);
      }
      List<Tuple2<Integer, Integer>> pairs = new ArrayList<>();
      for (int i = 1; i <= 5; i++) {
        pairs.add(new Tuple2<>(i, i));
      }
      assertEquals(pairs, takeOrFail(zipped, 5), "zip(a, a)");
      List<Integer> twice = new ArrayList<>(takeOrFail(merged, 10));
      twice.sort(null);
      assertEquals(List.of(1, 1, 2, 2, 3, 3, 4, 4, 5, 5), twice, "merge(a, a)");
      assertEquals(Optional.empty(), merged.take(java.time.Duration.ofMillis(200)), "nothing more");
    }
  }
}

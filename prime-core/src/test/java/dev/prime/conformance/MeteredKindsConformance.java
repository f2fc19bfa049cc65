package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Chain;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.ServiceMetrics;
import dev.prime.Source;
import dev.prime.Tick;
import dev.prime.Token;
import dev.prime.VirtualClock;
import java.time.Duration;
import java.util.List;
import java.util.Set;
import java.util.TreeSet;
import java.util.concurrent.BlockingQueue;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.LinkedBlockingQueue;
import java.util.concurrent.TimeUnit;
import java.util.stream.Collectors;
import org.junit.jupiter.api.Test;

/**
 * What is metered (architecture, <i>Metrics</i>, "What is metered"): every chain that runs logic
 * (made of a block, every template, collectors and isolated users included), every filter,
 * flat-map and listener, every event source, generic service, combinator and timer; "Linked
 * chains are not metered (their parts are)", and neither are the sources services publish to,
 * nor readers.
 */
public interface MeteredKindsConformance extends ConformanceBase {

  /** The metered names of a core with one node of each kind are exactly the documented ones. */
  @Test
  default void exactlyTheDocumentedKindsOfNodeAreMetered() {
    try (PrimeCore core = newCore(CoreConfig.builder().metrics(true).build())) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> numbers = core.source("numbers", events);
      Chain<Integer, Integer> linked =
          core.link(core.chain("inc", (Integer x) -> x + 1), core.chain("dbl", (Integer x) -> 2 * x));
      numbers.then(linked).reader();
      numbers.filter(x -> x > 0);
      numbers.flatMap(x -> List.of(x));
      numbers.listen(x -> {});
      core.guard(x -> true, core.chain("guarded", (Integer x) -> x), (Integer x) -> x).toBlock();
      core.isolate(core.chain("shared", (Integer x) -> x)).newUser().toBlock();
      Chain<Token, Integer> collector = core.syncCollector(numbers);
      collector.toBlock();
      core.merge(numbers, core.source("others", new EventBlock<Integer>()));
      core.timer("beat", Duration.ofHours(1));
      core.service("driver", () -> Thread.sleep(10));
      Set<String> metered =
          core.metrics().services().stream()
              .map(ServiceMetrics::name)
              .collect(Collectors.toCollection(TreeSet::new));
      Set<String> expected =
          new TreeSet<>(
              Set.of(
                  "numbers",
                  "others",
                  "inc",
                  "dbl",
                  "filter(numbers)",
                  "flatMap(numbers)",
                  "listen(numbers)",
                  "guarded",
                  "guard(guarded)",
                  "shared",
                  "shared@1",
                  "collect(numbers)",
                  "merge(numbers|others)",
                  "beat",
                  "driver"));
      assertEquals(expected, metered, "topology: " + core.topology().nodes());
    }
  }

  /**
   * A timer's {@code missed}, like an event source's, is what the plain readers of its source
   * missed ({@link ServiceMetrics}): ten ticks with a retention of 4 and a reader that reads only
   * after the tenth make the reader miss 6, and the timer's metrics say 6.
   */
  @Test
  default void aTimerCountsWhatTheReadersOfItsTicksMissed() throws InterruptedException {
    VirtualClock clock = new VirtualClock();
    CoreConfig config =
        CoreConfig.builder().clock(clock).metrics(true).sourceRetention(4).build();
    try (PrimeCore core = newCore(config)) {
      Source<Tick> beat = core.timer("beat", Duration.ofMillis(10));
      Reader<Tick> late = beat.reader();
      CountDownLatch tenth = new CountDownLatch(1);
      beat.listen(
          tick -> {
            if (tick.count() == 10) {
              tenth.countDown();
            }
          });
      core.start();
      clock.advance(Duration.ofMillis(100));
      assertTrue(tenth.await(patience().toMillis(), TimeUnit.MILLISECONDS), "ten ticks published");
      assertEquals(7, takeOrFail(late).count(), "the oldest retained tick");
      assertEquals(6, late.missed());
      ServiceMetrics metered = core.metrics().service("beat");
      assertEquals(6, metered.missed(), metered.toString());
    }
  }

  /**
   * A combinator's {@code missed}, like a timer's, is what the plain readers of its source missed
   * ({@link ServiceMetrics}): ten values merged with a retention of 4 and a reader of the merge
   * that reads only after the tenth make the reader miss 6, and the merge's metrics say 6. Each
   * value is published once the merge emitted the one before, as on Optimus the merge reads its
   * inputs through readers that miss what falls more than the retention behind (architecture.md,
   * <i>Combinators</i>, "Inputs").
   */
  @Test
  default void aCombinatorCountsWhatTheReadersOfItsOutputMissed() throws InterruptedException {
    CoreConfig config = CoreConfig.builder().metrics(true).sourceRetention(4).build();
    try (PrimeCore core = newCore(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> merged =
          core.merge(
              core.source("numbers", events), core.source("others", new EventBlock<Integer>()));
      Reader<Integer> late = merged.reader();
      BlockingQueue<Integer> emitted = new LinkedBlockingQueue<>();
      merged.listen(emitted::add);
      core.start();
      for (int i = 1; i <= 10; i++) {
        events.publish(i);
        assertEquals(
            i, emitted.poll(patience().toMillis(), TimeUnit.MILLISECONDS), "value " + i + " merged");
      }
      assertEquals(List.of(7, 8, 9, 10), takeOrFail(late, 4), "the values the source retains");
      assertEquals(6, late.missed(), "what the reader missed");
      ServiceMetrics metered = core.metrics().service("merge(numbers|others)");
      assertEquals(6, metered.missed(), metered.toString());
    }
  }
}

package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;

import dev.prime.Chain;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.ServiceMetrics;
import dev.prime.Source;
import dev.prime.Token;
import java.time.Duration;
import java.util.List;
import java.util.Set;
import java.util.TreeSet;
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
}

package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Source;
import java.util.List;
import org.junit.jupiter.api.Test;

/**
 * Linking is variant as {@link java.util.function.Function#andThen} is: the next chain or block
 * may take any supertype of what comes out, and a block may return a subtype of the wanted
 * output. This file only compiles with that variance; its tests run the linked chains on every
 * media (a fused media must call the very block given, not a wrapper).
 */
public interface LinkVarianceConformance extends ConformanceBase {

  /** A block of the most general input, as a logging or formatting block often is. */
  Block<Object, String> DESCRIBE = value -> "<" + value + ">";

  @Test
  default void aChainLinksToABlockOrChainOfASupertypeInput() {
    try (PrimeCore core = newCore()) {
      Chain<Integer, Integer> inc = core.chain("inc", (Integer x) -> x + 1);
      Chain<Integer, String> described = inc.then(DESCRIBE);
      Chain<Integer, Integer> twice = core.chain("twice", (Integer x) -> 2 * x);
      Chain<Object, String> describe = core.chain("describe", DESCRIBE);
      Chain<Integer, String> linked = twice.then(describe);
      Chain<Integer, Integer> first = core.chain("first", (Integer x) -> x - 1);
      Chain<Number, String> numberName = core.chain("number", (Number n) -> "#" + n.intValue());
      Chain<Integer, String> viaCore = core.link(first, numberName);
      core.start();
      assertEquals("<2>", described.toBlock().process(1));
      assertEquals("<6>", linked.toBlock().process(3));
      assertEquals("#9", viaCore.toBlock().process(10));
    }
  }

  @Test
  default void aBlockMayReturnASubtypeOfTheWantedOutput() {
    try (PrimeCore core = newCore()) {
      Block<Number, Integer> floor = n -> (int) Math.floor(n.doubleValue());
      Chain<Double, Double> half = core.chain("half", (Double x) -> x / 2);
      Chain<Double, Number> floored = half.then(floor);
      Chain<Double, Object> described = core.chain("half2", (Double x) -> x / 2).then(DESCRIBE);
      core.start();
      assertEquals(2, floored.toBlock().process(5.0));
      assertEquals("<2.5>", described.toBlock().process(5.0));
    }
  }

  @Test
  default void aSourceLinksToABlockOrChainOfASupertypeInput() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> numbers = core.source("numbers", events);
      Reader<String> viaBlock = numbers.then(DESCRIBE).reader();
      Reader<String> viaChain = numbers.then(core.chain("describe", DESCRIBE)).reader();
      Reader<String> viaCore =
          core.link(numbers, core.chain("name", (Number n) -> "#" + n)).reader();
      Block<Number, Long> widen = Number::longValue;
      Source<Number> widened = numbers.then(widen);
      Reader<Number> viaWidened = widened.reader();
      core.start();
      events.publish(1);
      events.publish(2);
      assertEquals(List.of("<1>", "<2>"), takeOrFail(viaBlock, 2));
      assertEquals(List.of("<1>", "<2>"), takeOrFail(viaChain, 2));
      assertEquals(List.of("#1", "#2"), takeOrFail(viaCore, 2));
      assertEquals(List.of(1L, 2L), takeOrFail(viaWidened, 2));
    }
  }
}

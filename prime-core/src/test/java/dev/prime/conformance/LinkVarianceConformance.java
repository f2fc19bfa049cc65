package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.Tuple2;
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
  default void templatesTakeChainsOfASupertypeInputAndASubtypeOutput() {
    try (PrimeCore core = newCore()) {
      Chain<Object, String> describe = core.chain("describe", DESCRIBE);
      Chain<Integer, String> count = core.chain("count", (Integer x) -> "n=" + x);
      Chain<Integer, CharSequence> branched =
          core.ifThenElse((Integer x) -> x > 0, describe, count);
      Chain<Number, Integer> floor = core.chain("floor", (Number n) -> n.intValue());
      Chain<List<Double>, List<Number>> floors = core.forEach(floor);
      Chain<Object, String> describe2 = core.chain("describe2", DESCRIBE);
      Chain<Integer, Integer> twice = core.chain("twice", (Integer x) -> 2 * x);
      Chain<Integer, Tuple2<String, Integer>> both = core.union(describe2, twice);
      Chain<Number, Integer> floor2 = core.chain("floor2", (Number n) -> n.intValue());
      Chain<Double, Number> guarded = core.guard((Double x) -> x >= 0, floor2, x -> -1L);
      core.start();
      Block<Integer, CharSequence> branchedBlock = branched.toBlock();
      assertEquals("<5>", branchedBlock.process(5));
      assertEquals("n=-5", branchedBlock.process(-5));
      assertEquals(List.of(1, 2), floors.toBlock().process(List.of(1.5, 2.5)));
      assertEquals(new Tuple2<>("<3>", 6), both.toBlock().process(3));
      Block<Double, Number> guardedBlock = guarded.toBlock();
      assertEquals(2, guardedBlock.process(2.7));
      assertEquals(-1L, guardedBlock.process(-2.7));
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

package dev.prime.radiant;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.ChainFailedException;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Tuple2;
import dev.prime.liberty.LibertyCore;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.List;
import java.util.function.Function;
import org.junit.jupiter.api.AfterEach;
import org.junit.jupiter.api.Test;

/** Radiant and Liberty blocks and chains inside each other. */
class MixedMediaTest {
  private final RadiantCore radiant = new RadiantCore();
  private final LibertyCore liberty = new LibertyCore();

  @AfterEach
  void close() {
    radiant.close();
    liberty.close();
  }

  /** A public block class: Radiant calls it by its own type. */
  public static final class Increment implements Block<Integer, Integer> {
    @Override
    public Integer process(Integer x) {
      return x + 1;
    }
  }

  /**
   * What a call gives, as text: the result, or the throwable's class, its chain name if it names
   * one, its message and its cause's class and message.
   */
  @SuppressWarnings({"unchecked", "rawtypes"})
  private static String outcome(Function<PrimeCore, Block> shape, Object input, PrimeCore core) {
    try (core) {
      Block block = shape.apply(core);
      core.start();
      try {
        return "returned " + block.process(input);
      } catch (Throwable t) {
        String chain = t instanceof ChainFailedException e ? " chain " + e.chainName() : "";
        Throwable cause = t.getCause();
        return t.getClass().getName() + chain + ": " + t.getMessage()
            + (cause == null ? "" : " / cause " + cause.getClass().getName() + ": "
                + cause.getMessage());
      }
    }
  }

  /**
   * "A block's exception reaches the caller as ChainFailedException(chain, cause) exactly as in
   * Liberty": for every shape Radiant fuses, a throwing block, a throwing condition or substitute,
   * an input of the wrong type and a null list fail with the same exception, chain name, message
   * and cause on both media, and the same calls return the same results.
   */
  @Test
  @SuppressWarnings({"unchecked", "rawtypes"})
  void everyFusedShapeFailsExactlyAsOnLiberty() {
    RuntimeException boom = new IllegalStateException("boom");
    Block<Integer, Integer> throwing = RadiantTemplatesTest.throwing(boom);
    List<Function<PrimeCore, Block>> shapes =
        List.of(
            c -> c.chain("leaf", new Increment()).toBlock(),
            c -> c.chain("a", new Increment()).then(c.chain("b", throwing))
                .then(c.chain("c", new Increment())).toBlock(),
            c -> c.chain("a", (Integer x) -> (Integer) null).then(c.chain("b", new Increment()))
                .toBlock(),
            c -> c.forEach(c.chain("body", new Increment())).toBlock(),
            c -> c.forEach(c.chain("a", new Increment()).then(c.chain("b", throwing))).toBlock(),
            c -> c.union(c.chain("u1", new Increment()), c.chain("u2", throwing)).toBlock(),
            c -> c.ifThenElse((Integer x) -> x > 0, c.chain("t", throwing), c.chain("f",
                new Increment())).toBlock(),
            c -> c.guard((Integer x) -> x > 0, c.chain("g", new Increment()),
                (Integer x) -> {
                  throw new UnsupportedOperationException("no substitute for " + x);
                }).toBlock(),
            c -> c.fork(c.chain("forked", throwing), new EventBlock<Integer>()).toBlock());
    List<Object> inputs = Arrays.asList(1, -1, "text", null, List.of(1, 2), List.of("x"));
    List<String> differences = new ArrayList<>();
    int compared = 0;
    int failed = 0;
    for (int s = 0; s < shapes.size(); s++) {
      for (Object input : inputs) {
        String onLiberty = outcome(shapes.get(s), input, new LibertyCore());
        String onRadiant = outcome(shapes.get(s), input, new RadiantCore());
        compared++;
        failed += onRadiant.startsWith(ChainFailedException.class.getName()) ? 1 : 0;
        if (!onLiberty.equals(onRadiant)) {
          differences.add("shape " + s + ", input " + input + ": Liberty " + onLiberty
              + " | Radiant " + onRadiant);
        }
      }
    }
    assertEquals(shapes.size() * inputs.size(), compared);
    assertTrue(failed > compared / 2, failed + " of " + compared + " calls failed");
    assertEquals(List.of(), differences);
  }

  @Test
  void aLibertyBlockIsALeafOfARadiantChain() {
    Block<Integer, Integer> composed =
        liberty.chain((Integer x) -> x + 1).then((Integer x) -> x * 2).toBlock();
    Block<Integer, String> fused =
        radiant.chain(composed).then((Integer x) -> "=" + x).toBlock();
    assertEquals("=8", fused.process(3));
  }

  @Test
  void aLibertyChainLinkedIntoARadiantChainIsConsumedAndCalled() {
    Chain<Integer, Integer> libertyChain = liberty.chain("lib", (Integer x) -> x * 3);
    Block<Integer, Integer> fused =
        radiant.chain((Integer x) -> x + 1).then(libertyChain).then((Integer x) -> x - 1)
            .toBlock();
    assertEquals(8, fused.process(2));
    assertThrows(dev.prime.ChainAlreadyUsedException.class, libertyChain::toBlock);
  }

  @Test
  void aFailureInsideTheLibertyPartNamesTheLibertyChain() {
    RuntimeException boom = new IllegalStateException("boom");
    Chain<Integer, Integer> libertyChain =
        liberty.chain("liberty-leaf", RadiantTemplatesTest.<Integer>throwing(boom));
    Block<Integer, Integer> fused =
        radiant.chain("radiant-leaf", (Integer x) -> x).then(libertyChain).toBlock();
    ChainFailedException e = assertThrows(ChainFailedException.class, () -> fused.process(1));
    assertEquals("liberty-leaf", e.chainName());
    assertSame(boom, e.getCause());
  }

  @Test
  void aFusedRadiantBlockRunsInsideALibertyChain() {
    Block<Integer, Integer> fused =
        radiant.chain((Integer x) -> x + 1)
            .then(radiant.union(radiant.chain((Integer x) -> x * 10), radiant.chain((Integer x) -> x)))
            .then((Tuple2<Integer, Integer> t) -> t.first() + t.second() - 2)
            .toBlock();
    Block<Integer, Integer> outer =
        liberty.chain(fused).then((Integer x) -> x + 5).toBlock();
    assertEquals(25, outer.process(1)); // 2 -> (20, 2) -> 20 -> 25
  }

  @Test
  void aFailureInsideTheFusedPartNamesTheRadiantLeaf() {
    RuntimeException boom = new ArithmeticException("boom");
    Block<Integer, Integer> fused =
        radiant.chain("fine", (Integer x) -> x)
            .then(radiant.chain("radiant-failing", RadiantTemplatesTest.<Integer>throwing(boom)))
            .toBlock();
    Block<Integer, Integer> outer =
        liberty.chain("outer", fused).then((Integer x) -> x).toBlock();
    ChainFailedException e = assertThrows(ChainFailedException.class, () -> outer.process(1));
    assertEquals("radiant-failing", e.chainName());
    assertSame(boom, e.getCause());
  }
}

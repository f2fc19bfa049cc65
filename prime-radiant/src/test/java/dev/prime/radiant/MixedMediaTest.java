package dev.prime.radiant;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.ChainFailedException;
import dev.prime.Tuple2;
import dev.prime.liberty.LibertyCore;
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

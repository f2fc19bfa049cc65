package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.ChainFailedException;
import dev.prime.PrimeCore;
import dev.prime.conformance.BlockKinds.Kind;
import java.io.IOException;
import java.util.ArrayList;
import java.util.List;
import org.junit.jupiter.api.Test;

/**
 * A block may be of any kind of class a user writes (public or not, its process inherited or a
 * default method, generic, an enum constant, anonymous, a lambda, a method reference, a proxy):
 * every media runs it as written, in a linked chain and in templates, and its failure reaches the
 * caller as a {@code ChainFailedException} naming its chain, the block's own throwable the cause,
 * made in the block's own code (the top frame of its stack trace). A media that generates code
 * calls some of these classes by their own type and the others through {@code Block}: both ways
 * behave alike.
 */
public interface BlockKindsConformance extends ConformanceBase {

  @Test
  default void aLinkedChainOfEveryKindOfBlockClassRunsEachBlockOnce() {
    try (PrimeCore core = newCore()) {
      List<Kind> kinds = BlockKinds.all();
      Chain<Integer, Integer> chain = core.chain(kinds.get(0).name(), kinds.get(0).block());
      for (Kind kind : kinds.subList(1, kinds.size())) {
        chain = chain.then(core.chain(kind.name(), kind.block()));
      }
      core.start();
      Block<Integer, Integer> block = chain.toBlock();
      assertEquals(BlockKinds.sum(), block.process(0));
      assertEquals(BlockKinds.sum() + 5, block.process(5));
    }
  }

  @Test
  default void templatesOfEveryKindOfBlockAndPredicateClassRunAsWritten() {
    try (PrimeCore core = newCore()) {
      List<Kind> a = BlockKinds.all();
      List<Kind> b = BlockKinds.all();
      List<Block<Integer, Integer>> blocks = new ArrayList<>();
      for (int i = 0; i < a.size(); i++) {
        Kind then = a.get(i);
        Kind otherwise = b.get((i + 1) % b.size());
        blocks.add(
            core.ifThenElse(
                    i % 2 == 0 ? new BlockKinds.IsEven() : BlockKinds.isPositive(),
                    core.chain("then-" + then.name(), then.block()),
                    core.chain("else-" + otherwise.name(), otherwise.block()))
                .toBlock());
      }
      Block<List<Integer>, List<Integer>> each =
          core.forEach(core.chain("each", new BlockKinds.Generic<Integer>())).toBlock();
      Block<Integer, Integer> guarded =
          core.guard(
                  BlockKinds.isPositive(),
                  core.chain("guarded", BlockKinds.Singleton.INSTANCE),
                  new BlockKinds.InheritsProcess())
              .toBlock();
      core.start();
      for (int i = 0; i < blocks.size(); i++) {
        int input = i % 2 == 0 ? 2 : -3; // even and positive: then; odd and negative: otherwise
        int adds = i % 2 == 0 ? a.get(i).adds() : b.get((i + 1) % b.size()).adds();
        assertEquals(input + adds, blocks.get(i).process(input), "the if/else of " + a.get(i));
      }
      assertEquals(List.of(33, 31), each.process(List.of(1, -1)));
      assertEquals(65, guarded.process(1), "a positive input runs the guarded chain");
      assertEquals(7, guarded.process(-1), "a negative one the substitute");
    }
  }

  @Test
  default void theFailureOfEveryKindOfBlockClassNamesItsChainWithTheBlocksOwnThrowable() {
    try (PrimeCore core = newCore()) {
      List<Block<Integer, Integer>> blocks = new ArrayList<>();
      List<Kind> kinds = BlockKinds.all();
      for (Kind kind : kinds) {
        blocks.add(
            core.chain("before-" + kind.name(), (Integer x) -> x)
                .then(core.chain(kind.name(), kind.block()))
                .toBlock());
      }
      core.start();
      for (int i = 0; i < kinds.size(); i++) {
        Kind kind = kinds.get(i);
        Block<Integer, Integer> block = blocks.get(i);
        ChainFailedException e =
            assertThrows(ChainFailedException.class, () -> block.process(BlockKinds.FAIL));
        assertEquals(kind.name(), e.chainName(), "the chain of the " + kind.name() + " named");
        Throwable cause = e.getCause();
        assertEquals(
            kind.name().equals("proxy") ? IllegalStateException.class : IOException.class,
            cause.getClass(),
            "the " + kind.name() + "'s own throwable: " + e);
        assertEquals(kind.name() + " failed on " + BlockKinds.FAIL, cause.getMessage());
        assertEquals(
            kind.failsIn(),
            cause.getStackTrace()[0].getClassName(),
            "the top frame of the cause is the " + kind.name() + "'s own code");
        assertEquals(7 + kind.adds(), block.process(7), "the " + kind.name() + " goes on");
      }
    }
  }
}

package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.ChainFailedException;
import dev.prime.PrimeCore;
import dev.prime.Tuple2;
import org.junit.jupiter.api.Assumptions;
import org.junit.jupiter.api.Test;

/**
 * Templates linked one after the other into a long chain compute and name their failures as a
 * short one does (architecture, <i>The model is what every media compiles</i>: Radiant splits a
 * generated class into segments past 200 call sites; <i>Errors</i>: a failure names the innermost
 * chain). Run on the media whose synchronous calls run the blocks in this process.
 */
public interface LongTemplateChainConformance extends ConformanceBase {

  /**
   * 600 templates (guards, if-then-elses, unions, forks and isolated users in turn), each around a
   * chain that adds 1, linked into one chain: a call adds 600, and a failure of the chain inside
   * the 451st template names that chain.
   */
  @Test
  default void aLongChainOfLinkedTemplatesComputesAndNamesTheFailingChain() {
    Assumptions.assumeTrue(blocksRunOnTheCallersThread(), "in-memory media only");
    int templates = 600;
    try (PrimeCore core = newCore()) {
      Chain<Integer, Integer> chain = core.chain((Integer x) -> x);
      for (int i = 1; i <= templates; i++) {
        String name = "step-" + i;
        boolean failing = i == 451;
        Chain<Integer, Integer> step =
            core.chain(
                name,
                (Integer x) -> {
                  if (failing && x < 0) {
                    throw new IllegalArgumentException("negative at " + name);
                  }
                  return x + 1;
                });
        Chain<Integer, Integer> template =
            switch (i % 5) {
              case 0 -> core.guard(x -> true, step, (Integer x) -> -1_000_000);
              case 1 -> core.ifThenElse(x -> x != Integer.MIN_VALUE, step, core.chain((Integer x) -> x));
              case 2 ->
                  core.union(step, core.chain((Integer x) -> 0))
                      .then((Tuple2<Integer, Integer> t) -> t.first() + t.second());
              case 3 -> core.fork(step, new dev.prime.EventBlock<Integer>());
              default -> core.isolate(step).newUser();
            };
        chain = chain.then(template);
      }
      Block<Integer, Integer> block = chain.toBlock();
      core.start();
      assertEquals(templates + 7, block.process(7));
      assertEquals(templates - 1, block.process(-1), "the 451st step fails only on a negative input");
      ChainFailedException e =
          assertThrows(ChainFailedException.class, () -> block.process(-1_000));
      assertEquals("step-451", e.chainName());
      assertEquals("negative at step-451", e.getCause().getMessage());
    }
  }
}

package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.ChainFailedException;
import dev.prime.PrimeCore;
import java.util.concurrent.Callable;
import java.util.concurrent.ExecutionException;
import java.util.concurrent.FutureTask;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Assumptions;
import org.junit.jupiter.api.Test;

/**
 * Chains of any length: a chain of 100,000 links builds and runs on a thread with the default
 * stack size, and a failing block in its middle is reported under its own chain's name. Nothing
 * in building, compiling or calling a chain may recurse once per link. Run on the media whose
 * synchronous calls run the blocks in this process ({@link #blocksRunOnTheCallersThread()});
 * a chain of 100,000 services is not a sensible topology on Optimus.
 */
public interface LongChainConformance extends ConformanceBase {

  /** Links in the long chains. */
  int LONG_CHAIN_LINKS = 100_000;

  /** Runs {@code work} on a new thread of the default stack size, bounded in time. */
  private <T> T onDefaultStack(Callable<T> work) throws Exception {
    FutureTask<T> task = new FutureTask<>(work);
    Thread thread = new Thread(task, "kit-default-stack");
    thread.start();
    try {
      return task.get(patience().toSeconds() * 5, TimeUnit.SECONDS);
    } catch (ExecutionException e) {
      if (e.getCause() instanceof Exception failure) {
        throw failure;
      }
      throw new AssertionError("the long chain failed on a default stack", e.getCause());
    } finally {
      thread.interrupt();
      thread.join(patience().toMillis());
    }
  }

  @Test
  default void aChainOfOneHundredThousandLinksBuildsAndRunsOnADefaultStack() throws Exception {
    Assumptions.assumeTrue(blocksRunOnTheCallersThread(), "in-memory media only");
    try (PrimeCore core = newCore()) {
      Block<Integer, Integer> block =
          onDefaultStack(
              () -> {
                Chain<Integer, Integer> chain = core.chain((Integer x) -> x + 1);
                for (int i = 1; i < LONG_CHAIN_LINKS; i++) {
                  chain = chain.then((Integer x) -> x + 1);
                }
                return chain.toBlock();
              });
      core.start();
      assertEquals(LONG_CHAIN_LINKS + 7, onDefaultStack(() -> block.process(7)));
      assertEquals(LONG_CHAIN_LINKS - 3, onDefaultStack(() -> block.process(-3)));
    }
  }

  @Test
  default void aFailingBlockInTheMiddleOfALongChainIsNamed() throws Exception {
    Assumptions.assumeTrue(blocksRunOnTheCallersThread(), "in-memory media only");
    try (PrimeCore core = newCore()) {
      Block<Integer, Integer> block =
          onDefaultStack(
              () -> {
                Chain<Integer, Integer> chain = core.chain((Integer x) -> x);
                for (int i = 1; i < LONG_CHAIN_LINKS; i++) {
                  chain =
                      i == LONG_CHAIN_LINKS / 2
                          ? chain.then(
                              core.chain(
                                  "middle",
                                  (Integer x) -> {
                                    if (x < 0) {
                                      throw new IllegalArgumentException("negative " + x);
                                    }
                                    return x;
                                  }))
                          : chain.then((Integer x) -> x);
                }
                return chain.toBlock();
              });
      core.start();
      assertEquals(5, onDefaultStack(() -> block.process(5)));
      ChainFailedException e =
          assertThrows(ChainFailedException.class, () -> onDefaultStack(() -> block.process(-1)));
      assertEquals("middle", e.chainName());
      assertEquals("negative -1", e.getCause().getMessage());
    }
  }
}

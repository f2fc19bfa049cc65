package dev.prime.liberty;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.ChainFailedException;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.ExecutionException;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.TimeoutException;
import java.util.function.Supplier;
import org.junit.jupiter.api.Test;

/**
 * Chains of 100,000 links build and run on a thread with the default stack size: Liberty neither
 * builds nor calls a chain by recursion proportional to its length.
 */
class LibertyLongChainTest {
  private static final int LINKS = 100_000;
  private static final int FAILING = 50_000;

  @Test
  void chainLinkedLeftToRightBuildsAndRuns() throws Exception {
    long result =
        onDefaultStack(
            () -> {
              try (LibertyCore core = new LibertyCore()) {
                Chain<Long, Long> chain = core.chain((Long x) -> x + 1);
                for (int i = 1; i < LINKS; i++) {
                  chain = chain.then((Long x) -> x + 1);
                }
                core.start();
                Block<Long, Long> block = chain.toBlock();
                block.process(0L);
                return block.process(7L);
              }
            });
    assertEquals(7L + LINKS, result);
  }

  @Test
  void chainLinkedRightToLeftBuildsAndRuns() throws Exception {
    long result =
        onDefaultStack(
            () -> {
              try (LibertyCore core = new LibertyCore()) {
                Chain<Long, Long> chain = core.chain((Long x) -> x * 2);
                for (int i = 1; i < LINKS; i++) {
                  chain = core.chain((Long x) -> x + 1).then(chain);
                }
                core.start();
                return chain.toBlock().process(0L);
              }
            });
    assertEquals(2L * (LINKS - 1), result, "the doubling block is the last one");
  }

  @Test
  void failingBlockInTheMiddleNamesItsChain() throws Exception {
    IllegalStateException boom = new IllegalStateException("boom at " + FAILING);
    ChainFailedException failure =
        onDefaultStack(
            () -> {
              try (LibertyCore core = new LibertyCore()) {
                Chain<Long, Long> chain = core.chain("step-0", (Long x) -> x + 1);
                for (int i = 1; i < LINKS; i++) {
                  Block<Long, Long> block =
                      i == FAILING
                          ? x -> {
                            throw boom;
                          }
                          : x -> x + 1;
                  chain = chain.then(core.chain("step-" + i, block));
                }
                core.start();
                Block<Long, Long> block = chain.toBlock();
                return assertThrows(ChainFailedException.class, () -> block.process(0L));
              }
            });
    assertEquals("step-" + FAILING, failure.chainName());
    assertSame(boom, failure.getCause());
    assertTrue(failure.getMessage().contains("step-" + FAILING), failure.getMessage());
  }

  /** Runs the task on a new thread with the JVM's default stack size; a stack overflow fails. */
  private static <T> T onDefaultStack(Supplier<T> task)
      throws InterruptedException, ExecutionException, TimeoutException {
    CompletableFuture<T> result = new CompletableFuture<>();
    Thread thread =
        new Thread(
            () -> {
              try {
                result.complete(task.get());
              } catch (Throwable e) {
                result.completeExceptionally(e);
              }
            },
            "default-stack");
    thread.start();
    try {
      return result.get(2, TimeUnit.MINUTES);
    } catch (ExecutionException e) {
      if (e.getCause() instanceof Error error) {
        throw error; // a StackOverflowError, or an assertion that failed on that thread
      }
      throw e;
    } finally {
      thread.join(TimeUnit.SECONDS.toMillis(10));
    }
  }
}

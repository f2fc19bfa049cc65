package dev.prime.radiant;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import java.lang.reflect.Field;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.ExecutorService;
import java.util.concurrent.Executors;
import java.util.concurrent.Future;
import java.util.concurrent.TimeUnit;
import java.util.function.Predicate;
import org.junit.jupiter.api.AfterEach;
import org.junit.jupiter.api.Test;

/** Call sites typed by the block's own class work for every way a class can get its method. */
class CallSiteTypesTest {
  private final RadiantCore core = new RadiantCore();

  @AfterEach
  void close() {
    core.close();
  }

  /** Declares process in a superclass that the fused class cannot name. */
  abstract static class HiddenBase implements Block<Integer, Integer> {
    @Override
    public Integer process(Integer x) {
      return x * 2;
    }
  }

  /** Public, but its process is inherited. */
  public static final class Doubler extends HiddenBase {}

  /** A public predicate class. */
  public static final class IsEven implements Predicate<Integer> {
    @Override
    public boolean test(Integer x) {
      return x % 2 == 0;
    }
  }

  /** Not public: called through Block. */
  private static final class Negate implements Block<Integer, Integer> {
    @Override
    public Integer process(Integer x) {
      return -x;
    }
  }

  @Test
  void inheritedBridgedAndPrivateBlocksAreCalledCorrectly() throws Exception {
    Block<Integer, Integer> block =
        core.ifThenElse(
                new IsEven(), core.chain(new Doubler()), core.chain(new Negate()))
            .then(new Doubler())
            .toBlock();
    assertEquals(8, block.process(2));
    assertEquals(-6, block.process(3));
    List<Class<?>> types = new ArrayList<>();
    for (Field field : block.getClass().getDeclaredFields()) {
      types.add(field.getType());
    }
    assertEquals(List.of(IsEven.class, Doubler.class, Block.class, Doubler.class), types);
  }

  /** Adds its own constant; public, so the fused class holds it by its own type. */
  public static final class Add implements Block<Integer, Integer> {
    private final int n;

    Add(int n) {
      this.n = n;
    }

    @Override
    public Integer process(Integer x) {
      return x + n;
    }
  }

  /**
   * Compiling is thread-safe: chains compiled at once on several threads (each with a core of its
   * own, since one core compiles its chains under its declaration lock) each get their own blocks
   * in their own class's constants, never another thread's.
   */
  @Test
  void chainsCompiledOnManyThreadsAtOnceEachKeepTheirOwnBlocks() throws Exception {
    int threads = 4;
    int chains = 100;
    ExecutorService pool = Executors.newFixedThreadPool(threads);
    CountDownLatch go = new CountDownLatch(1);
    try {
      List<Future<List<String>>> results = new ArrayList<>();
      for (int t = 0; t < threads; t++) {
        int thread = t;
        results.add(
            pool.submit(
                () -> {
                  assertTrue(go.await(30, TimeUnit.SECONDS));
                  List<String> wrong = new ArrayList<>();
                  try (RadiantCore own = new RadiantCore()) {
                    for (int i = 0; i < chains; i++) {
                      int n = thread * 100_000 + i * 10;
                      Block<Integer, Integer> block =
                          own.chain(new Add(n))
                              .then(
                                  own.ifThenElse(
                                      (Integer x) -> x >= n,
                                      own.chain(new Add(1)),
                                      own.chain(new Add(-1))))
                              .toBlock();
                      int got = block.process(0);
                      if (got != n + 1) {
                        wrong.add("thread " + thread + ", chain " + i + ": " + got);
                      }
                    }
                  }
                  return wrong;
                }));
      }
      go.countDown();
      for (Future<List<String>> result : results) {
        assertEquals(List.of(), result.get(120, TimeUnit.SECONDS));
      }
    } finally {
      pool.shutdownNow();
    }
  }

  @Test
  void aFusedBlockMayBeCalledFromManyThreadsAtOnce() throws Exception {
    Block<List<Integer>, List<Integer>> block =
        core.forEach(core.chain((Integer x) -> x + 1).then((Integer x) -> x * x)).toBlock();
    ExecutorService pool = Executors.newFixedThreadPool(4);
    try {
      List<Future<Boolean>> results = new ArrayList<>();
      for (int t = 0; t < 4; t++) {
        int offset = t * 1000;
        results.add(
            pool.submit(
                () -> {
                  for (int i = 0; i < 2000; i++) {
                    int x = offset + i;
                    if (!block.process(List.of(x, x + 1))
                        .equals(List.of((x + 1) * (x + 1), (x + 2) * (x + 2)))) {
                      return false;
                    }
                  }
                  return true;
                }));
      }
      for (Future<Boolean> result : results) {
        assertEquals(true, result.get(30, TimeUnit.SECONDS));
      }
    } finally {
      pool.shutdownNow();
    }
  }
}

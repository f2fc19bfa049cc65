package dev.prime.radiant;

import static org.junit.jupiter.api.Assertions.assertEquals;

import dev.prime.Block;
import java.lang.reflect.Field;
import java.util.ArrayList;
import java.util.List;
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

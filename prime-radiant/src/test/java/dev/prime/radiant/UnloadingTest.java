package dev.prime.radiant;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import java.lang.management.ClassLoadingMXBean;
import java.lang.management.ManagementFactory;
import java.lang.ref.ReferenceQueue;
import java.lang.ref.WeakReference;
import java.util.ArrayList;
import java.util.List;
import org.junit.jupiter.api.Test;

/** Dropped fused chains take their generated classes with them. */
class UnloadingTest {
  private static final int CHAINS = 5000;

  @Test
  void manyDroppedChainsDoNotGrowLoadedClassesWithoutBound() throws InterruptedException {
    ClassLoadingMXBean classLoading = ManagementFactory.getClassLoadingMXBean();
    ReferenceQueue<Class<?>> unloaded = new ReferenceQueue<>();
    List<WeakReference<Class<?>>> classes = new ArrayList<>(CHAINS);
    long loadedBefore;
    try (RadiantCore core = new RadiantCore()) {
      // one chain first, so the classes every fused chain uses are already loaded
      core.chain((Integer x) -> x).toBlock().process(0);
      loadedBefore = classLoading.getLoadedClassCount();
      for (int i = 0; i < CHAINS; i++) {
        Block<Integer, Integer> block =
            core.chain((Integer x) -> x + 1)
                .then(core.ifThenElse((Integer x) -> x > 0, core.chain((Integer x) -> x * 2),
                    core.chain((Integer x) -> -x)))
                .toBlock();
        assertEquals(2 * (i + 1), block.process(i));
        classes.add(new WeakReference<>(block.getClass(), unloaded));
      }
    }
    assertTrue(
        classLoading.getLoadedClassCount() - loadedBefore >= CHAINS / 2,
        "the chains were really compiled into classes");

    int collected = 0;
    for (int attempt = 0; attempt < 20 && collected < CHAINS; attempt++) {
      System.gc();
      while (unloaded.remove(200) != null) {
        collected++;
      }
    }
    assertEquals(CHAINS, collected, "generated classes that became unreachable");
    long growth = classLoading.getLoadedClassCount() - loadedBefore;
    assertTrue(growth < CHAINS / 10, "loaded classes grew by " + growth + " for " + CHAINS
        + " dropped chains");
  }
}

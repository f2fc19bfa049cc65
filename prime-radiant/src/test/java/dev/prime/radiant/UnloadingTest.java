package dev.prime.radiant;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.radiant.internal.FusedCompiler;
import java.lang.management.ClassLoadingMXBean;
import java.lang.management.ManagementFactory;
import java.lang.reflect.Field;
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
    long totalBefore;
    try (RadiantCore core = new RadiantCore()) {
      // one chain first, so the classes every fused chain uses are already loaded
      core.chain((Integer x) -> x).toBlock().process(0);
      loadedBefore = classLoading.getLoadedClassCount();
      totalBefore = classLoading.getTotalLoadedClassCount();
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
    // counted since the JVM started: classes of earlier tests unloaded meanwhile do not offset it
    assertTrue(
        classLoading.getTotalLoadedClassCount() - totalBefore >= CHAINS,
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

  @Test
  void aDroppedBlockIsUnloadedWhileItsCoreStaysOpen() throws InterruptedException {
    try (RadiantCore core = new RadiantCore()) {
      core.start();
      ReferenceQueue<Object> unloaded = new ReferenceQueue<>();
      List<WeakReference<Object>> dropped = new ArrayList<>();
      for (int i = 0; i < 50; i++) {
        compileRunAndDrop(core, i, unloaded, dropped);
      }
      int collected = 0;
      for (int attempt = 0; attempt < 20 && collected < dropped.size(); attempt++) {
        System.gc();
        while (unloaded.remove(200) != null) {
          collected++;
        }
      }
      assertEquals(dropped.size(), collected,
          "fused classes and loaders unloaded while the core that compiled them is open");
      assertFalse(core.isClosed());
      assertEquals(3, core.chain((Integer x) -> x + 1).toBlock().process(2), "the core still works");
    }
  }

  /** Compiles one chain of {@code core}, runs it once, and keeps weak references only. */
  private static void compileRunAndDrop(
      RadiantCore core, int i, ReferenceQueue<Object> unloaded, List<WeakReference<Object>> refs) {
    Block<Integer, Integer> block =
        core.chain("dropped-" + i, (Integer x) -> x + 1).then((Integer x) -> x * 2).toBlock();
    assertEquals(2 * (i + 1), block.process(i));
    refs.add(new WeakReference<>(block.getClass(), unloaded));
    refs.add(new WeakReference<>(block.getClass().getClassLoader(), unloaded));
  }

  @Test
  void aChainSplitIntoSegmentsIsUnloadedWithAllItsClasses() throws InterruptedException {
    ReferenceQueue<Object> unloaded = new ReferenceQueue<>();
    List<WeakReference<Object>> classes = segmentedChainDropped(unloaded);
    assertEquals(2 + 3, classes.size(), "the driver, its loader and three segments");
    int collected = 0;
    for (int attempt = 0; attempt < 20 && collected < classes.size(); attempt++) {
      System.gc();
      while (unloaded.remove(200) != null) {
        collected++;
      }
    }
    assertEquals(classes.size(), collected, "the chain's classes and loader that were unloaded");
  }

  /** Compiles a chain of three segments, runs it, and drops it: weak references to its parts. */
  private static List<WeakReference<Object>> segmentedChainDropped(
      ReferenceQueue<Object> unloaded) {
    List<WeakReference<Object>> classes = new ArrayList<>();
    try (RadiantCore core = new RadiantCore()) {
      int length = FusedCompiler.MAX_SITES * 3;
      Chain<Integer, Integer> chain = core.chain((Integer x) -> x + 1);
      for (int i = 1; i < length; i++) {
        chain = chain.then((Integer x) -> x + 1);
      }
      Block<Integer, Integer> block = chain.toBlock();
      assertEquals(length, block.process(0));
      classes.add(new WeakReference<>(block.getClass(), unloaded));
      classes.add(new WeakReference<>(block.getClass().getClassLoader(), unloaded));
      for (Field segment : block.getClass().getDeclaredFields()) {
        classes.add(new WeakReference<>(segment.getType(), unloaded));
      }
    }
    return classes;
  }
}

package dev.prime.radiant;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.PrimeCore;
import dev.prime.soak.Footprint;
import dev.prime.soak.Soak;
import dev.prime.soak.Soak.Timing;
import java.lang.management.ClassLoadingMXBean;
import java.lang.management.ManagementFactory;
import java.lang.ref.WeakReference;
import java.util.ArrayList;
import java.util.List;
import org.junit.jupiter.api.Test;

/**
 * Radiant cores opened and closed many times in one JVM, and one core of many services, leave
 * nothing behind: no thread, file descriptor, process, heap or generated class that grows with the
 * count.
 */
class RadiantSoakTest {
  private static final int CYCLES = 300;

  /**
   * Heap growth allowed over a run. Measured: 300 cycles end within 0.2 MiB of where they began
   * (-80 KiB to +170 KiB), the fan-out and the line within 110 KiB (Liberty) and 240 KiB
   * (Radiant). The bound leaves room for soft references and caches a loaded machine may keep; a
   * closed core kept reachable (about 4 KiB each) is caught by {@link Footprint#assertCollected}
   * instead, and a leak of 7 KiB a cycle by this bound.
   */
  private static final long HEAP_BOUND = 2L << 20;

  @Test
  void openingAndClosingManyCoresLeavesNothingBehind() throws InterruptedException {
    ClassLoadingMXBean classLoading = ManagementFactory.getClassLoadingMXBean();
    Soak.cycles(RadiantCore::new, 5, 20);
    Footprint before = Footprint.take();
    long unloadedBefore = classLoading.getUnloadedClassCount();
    // Besides the generated classes, the JVM loads some of its own classes once, late (seen: 44
    // to 55 over the last 200 cycles, the same after 600 more); a class kept a cycle adds 200.
    List<WeakReference<PrimeCore>> closed = new ArrayList<>(Soak.cycles(RadiantCore::new, CYCLES / 3, 20));
    Footprint.settledHeap();
    long loadedThen = classLoading.getLoadedClassCount();
    closed.addAll(Soak.cycles(RadiantCore::new, CYCLES - CYCLES / 3, 20));
    Footprint.take().assertNothingLeftSince(before, CYCLES, HEAP_BOUND);
    Footprint.assertCollected(closed);
    long unloaded = classLoading.getUnloadedClassCount() - unloadedBefore;
    long growth = classLoading.getLoadedClassCount() - loadedThen;
    // three chains a cycle, each compiled into a class of its own
    assertTrue(unloaded >= 3 * CYCLES - 30, unloaded + " classes unloaded over " + CYCLES
        + " cycles of 3 generated classes each");
    assertTrue(growth < (CYCLES - CYCLES / 3) / 2, "loaded classes grew by " + growth + " over the last "
        + (CYCLES - CYCLES / 3) + " cycles");
  }

  @Test
  void aFanOutOf500AndALineOf200DeliverEveryValueAndCloseLeavingNothing()
      throws InterruptedException {
    Soak.fanOut(new RadiantCore(), 10, 100, () -> 0);
    Footprint before = Footprint.take();
    Timing fan = Soak.fanOut(new RadiantCore(), 500, 1000, () -> 0);
    Timing line = Soak.line(new RadiantCore(), 200, 1000, () -> 0);
    System.out.println("Radiant: " + fan + ", " + line);
    // two threads a chain: its service, and the listener of its output
    assertEquals(2 * 500, fan.primeThreads(), "threads of the fan-out");
    // the line is fused into one chain: one service and the listener
    assertEquals(2, line.primeThreads(), "threads of the line");
    assertTrue(fan.closeMs() < 10_000, "close() of the fan-out took " + fan.closeMs() + " ms");
    Footprint.take().assertNothingLeftSince(before, 2, HEAP_BOUND);
  }
}

package dev.prime.liberty;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.PrimeCore;
import dev.prime.soak.Footprint;
import dev.prime.soak.Soak;
import dev.prime.soak.Soak.Timing;
import java.lang.ref.WeakReference;
import java.util.List;
import org.junit.jupiter.api.Test;

/**
 * Liberty cores opened and closed many times in one JVM, and one core of many services, leave
 * nothing behind: no thread, file descriptor, process or heap that grows with the count.
 */
class LibertySoakTest {
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
    Soak.cycles(LibertyCore::new, 5, 20);
    Footprint before = Footprint.take();
    List<WeakReference<PrimeCore>> closed = Soak.cycles(LibertyCore::new, CYCLES, 20);
    Footprint.take().assertNothingLeftSince(before, CYCLES, HEAP_BOUND);
    Footprint.assertCollected(closed);
  }

  @Test
  void aFanOutOf500AndALineOf200DeliverEveryValueAndCloseLeavingNothing()
      throws InterruptedException {
    Soak.fanOut(new LibertyCore(), 10, 100, () -> 0);
    Footprint before = Footprint.take();
    Timing fan = Soak.fanOut(new LibertyCore(), 500, 1000, () -> 0);
    Timing line = Soak.line(new LibertyCore(), 200, 1000, () -> 0);
    System.out.println("Liberty: " + fan + ", " + line);
    // two threads a chain: its service, and the listener of its output
    assertEquals(2 * 500, fan.primeThreads(), "threads of the fan-out");
    // the line is fused into one chain: one service and the listener
    assertEquals(2, line.primeThreads(), "threads of the line");
    assertTrue(fan.closeMs() < 10_000, "close() of the fan-out took " + fan.closeMs() + " ms");
    Footprint.take().assertNothingLeftSince(before, 2, HEAP_BOUND);
  }
}

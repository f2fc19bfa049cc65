package dev.prime;

import static org.openjdk.jcstress.annotations.Expect.ACCEPTABLE;
import static org.openjdk.jcstress.annotations.Expect.FORBIDDEN;

import java.util.concurrent.atomic.AtomicInteger;
import org.openjdk.jcstress.annotations.Actor;
import org.openjdk.jcstress.annotations.Arbiter;
import org.openjdk.jcstress.annotations.Description;
import org.openjdk.jcstress.annotations.JCStressTest;
import org.openjdk.jcstress.annotations.Outcome;
import org.openjdk.jcstress.annotations.State;
import org.openjdk.jcstress.infra.results.II_Result;

/**
 * Two callers of one isolated block ({@link IsolateBlock}, the ticket queue of {@code
 * PrimeCore.isolate}): the block never runs for both at once, and both calls run. A waiter
 * checks at every look at the turn (interval 0), so it never sleeps in a slice.
 */
@JCStressTest
@Description("process(1) vs process(2) on one isolated block: one at a time, both run")
@Outcome(id = "0, 2", expect = ACCEPTABLE, desc = "never both inside, both ran")
@Outcome(expect = FORBIDDEN, desc = "both inside at once, or a call lost")
@State
public class IsolateExclusionStress {
  private final AtomicInteger inside = new AtomicInteger();
  private final AtomicInteger overlaps = new AtomicInteger();
  private final AtomicInteger ran = new AtomicInteger();
  private final Block<Integer, Integer> isolated =
      new IsolateBlock<>(
          x -> {
            if (inside.incrementAndGet() > 1) {
              overlaps.incrementAndGet();
            }
            ran.incrementAndGet();
            inside.decrementAndGet();
            return x;
          },
          () -> {},
          () -> false,
          0);

  /** The first caller. */
  @Actor
  public void first() {
    isolated.process(1);
  }

  /** The second caller. */
  @Actor
  public void second() {
    isolated.process(2);
  }

  /** Overlaps seen, and calls run. */
  @Arbiter
  public void arbiter(II_Result r) {
    r.r1 = overlaps.get();
    r.r2 = ran.get();
  }
}

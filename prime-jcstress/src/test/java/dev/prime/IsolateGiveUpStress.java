package dev.prime;

import static org.openjdk.jcstress.annotations.Expect.ACCEPTABLE;
import static org.openjdk.jcstress.annotations.Expect.FORBIDDEN;

import java.util.concurrent.TimeUnit;
import org.openjdk.jcstress.annotations.Actor;
import org.openjdk.jcstress.annotations.Arbiter;
import org.openjdk.jcstress.annotations.Description;
import org.openjdk.jcstress.annotations.JCStressTest;
import org.openjdk.jcstress.annotations.Outcome;
import org.openjdk.jcstress.annotations.State;
import org.openjdk.jcstress.infra.results.III_Result;

/**
 * Calls of one isolated block ({@link IsolateBlock}) from two threads (jcstress needs a CPU per
 * actor): one calls with 1 then 3; the other's caller has given up, so its call of 2 stops as
 * soon as it has to wait: while waiting (its ticket left to be skipped) or when its turn comes
 * (passing the turn on). Whichever way, no turn is lost: the call of 3 runs, and a call of 4,
 * made after all others ended, finds the block free at once. A waiter checks at every look at
 * the turn (interval 0); the call of 3 waits at most 10 s ({@code -9}, forbidden), and the call
 * of 4 must not wait at all ({@code -9} too).
 */
@JCStressTest
@Description("process(1), process(3) vs a caller that gave up, then process(4): no turn lost")
@Outcome(id = "2, 3, 4", expect = ACCEPTABLE, desc = "the second found the block free and ran")
@Outcome(id = "-1, 3, 4", expect = ACCEPTABLE, desc = "the second waited and stopped, not run")
@Outcome(expect = FORBIDDEN, desc = "a turn lost (a call waited in vain), or a call run twice")
@State
public class IsolateGiveUpStress {
  private static final long BOUND_NANOS = TimeUnit.SECONDS.toNanos(10);

  private final long started = System.nanoTime();
  private volatile Thread gaveUp;
  private volatile Thread mustNotWait;
  private final Block<Integer, Integer> isolated =
      new IsolateBlock<>(
          x -> x,
          () -> {
            if (Thread.currentThread() == mustNotWait) {
              throw new IllegalStateException("a call after all others ended had to wait");
            }
            if (System.nanoTime() - started > BOUND_NANOS) {
              throw new IllegalStateException("waited 10 s for a turn");
            }
          },
          () -> Thread.currentThread() == gaveUp,
          0);

  private int call(int x) {
    try {
      return isolated.process(x);
    } catch (IllegalStateException e) {
      return -9;
    } catch (PrimeException e) {
      return -1;
    }
  }

  /** A caller that calls twice: the second call may come behind the one that gave up. */
  @Actor
  public void first(III_Result r) {
    isolated.process(1);
    r.r2 = call(3);
  }

  /** The caller that gave up. */
  @Actor
  public void second(III_Result r) {
    gaveUp = Thread.currentThread();
    r.r1 = call(2);
  }

  /** A call after all others ended. */
  @Arbiter
  public void arbiter(III_Result r) {
    mustNotWait = Thread.currentThread();
    r.r3 = call(4);
  }
}

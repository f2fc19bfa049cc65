package dev.prime.selfcheck;

import static org.openjdk.jcstress.annotations.Expect.ACCEPTABLE;
import static org.openjdk.jcstress.annotations.Expect.FORBIDDEN;

import org.openjdk.jcstress.annotations.Actor;
import org.openjdk.jcstress.annotations.Description;
import org.openjdk.jcstress.annotations.JCStressTest;
import org.openjdk.jcstress.annotations.Outcome;
import org.openjdk.jcstress.annotations.State;
import org.openjdk.jcstress.infra.results.II_Result;

/**
 * Deliberately broken, to prove the runner fails the build: two publishers claim sequence numbers
 * of a ring without its lock (read, then write back one more), so both can claim the same slot and
 * one value overwrites the other. {@code JcstressRunTest} runs it alone and asserts that jcstress
 * reports the duplicate claim. Not part of the suite over Prime's classes (its package keeps it
 * out of that run's filter).
 */
@JCStressTest
@Description("claim without a lock: two publishers may claim one sequence number (must be caught)")
@Outcome(id = {"0, 1", "1, 0"}, expect = ACCEPTABLE, desc = "distinct sequence numbers")
@Outcome(expect = FORBIDDEN, desc = "both claimed one sequence number: a value overwritten")
@State
public class UnlockedClaimToy {
  private volatile int next;

  private int claim() {
    int sequence = next;
    for (int i = 0; i < 64; i++) {
      Thread.onSpinWait(); // the window a missing lock leaves open, widened to be seen quickly
    }
    next = sequence + 1;
    return sequence;
  }

  /** A publisher. */
  @Actor
  public void first(II_Result r) {
    r.r1 = claim();
  }

  /** Another publisher. */
  @Actor
  public void second(II_Result r) {
    r.r2 = claim();
  }
}

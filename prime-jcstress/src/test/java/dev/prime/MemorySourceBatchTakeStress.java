package dev.prime;

import static org.openjdk.jcstress.annotations.Expect.ACCEPTABLE;
import static org.openjdk.jcstress.annotations.Expect.FORBIDDEN;

import org.openjdk.jcstress.annotations.Actor;
import org.openjdk.jcstress.annotations.Description;
import org.openjdk.jcstress.annotations.JCStressTest;
import org.openjdk.jcstress.annotations.Outcome;
import org.openjdk.jcstress.annotations.State;
import org.openjdk.jcstress.infra.results.II_Result;

/**
 * Batch take vs publish: a service input with room for 2 values takes in batches ({@link
 * BatchReader#takeAvailable}) while one publisher publishes 1, 2, 3. Every value comes once, in
 * order, and the publisher reuses a slot only after the batch read it (a value read after its slot
 * was reused would show as 3 in place of 1). A batch ends at the values published when it began,
 * so 3 values through room for 2 take 2 or 3 batches, never 1.
 *
 * <p>The service starts a batch only once the publisher has said a value is there, so no batch
 * waits: a lost wake-up cannot hang this test (the termination tests check waking), and a value
 * that never arrives ends the test after {@link StressSources#BOUND} with the batches so far.
 *
 * <p>Result: the values taken as decimal digits (123), the number of batches (-9: interrupted).
 */
@JCStressTest
@Description("publish 1, 2, 3 into a gated ring of 2 vs batch takes: 123 in 2 or 3 batches")
@Outcome(id = "123, 2", expect = ACCEPTABLE, desc = "two batches: [1, 2] [3] or [1] [2, 3]")
@Outcome(id = "123, 3", expect = ACCEPTABLE, desc = "one value per batch")
@Outcome(expect = FORBIDDEN, desc = "a value lost, repeated, reordered or overwritten")
@State
public class MemorySourceBatchTakeStress {
  private final MemorySource<Integer> source = StressSources.source(2);

  @SuppressWarnings("unchecked")
  private final BatchReader<Integer> input =
      (BatchReader<Integer>) source.serviceInput("stress-service");

  private volatile int published; // how many values the publisher has published
  private int taken;
  private int digits;

  /** The publisher. */
  @Actor
  public void publisher() {
    for (int value = 1; value <= 3; value++) {
      source.publish(value);
      published = value;
    }
  }

  /** The service: at most 3 batches, each started once a value is there. */
  @Actor
  public void service(II_Result r) {
    int batches = 0;
    long deadline = System.nanoTime() + StressSources.BOUND.toNanos();
    try {
      while (taken < 3 && batches < 3 && System.nanoTime() - deadline < 0) {
        if (published > taken) {
          input.takeAvailable(this::accept);
          batches++;
        } else {
          Thread.onSpinWait();
        }
      }
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
      batches = -9;
    }
    r.r1 = digits;
    r.r2 = batches;
  }

  private boolean accept(Integer value) {
    digits = digits * 10 + value;
    taken++;
    return true;
  }
}

package dev.prime;

import static org.openjdk.jcstress.annotations.Expect.ACCEPTABLE;
import static org.openjdk.jcstress.annotations.Expect.FORBIDDEN;

import org.openjdk.jcstress.annotations.Actor;
import org.openjdk.jcstress.annotations.Description;
import org.openjdk.jcstress.annotations.JCStressTest;
import org.openjdk.jcstress.annotations.Mode;
import org.openjdk.jcstress.annotations.Outcome;
import org.openjdk.jcstress.annotations.Signal;
import org.openjdk.jcstress.annotations.State;

/**
 * Park and wake of a service's batch take with no waiting budget: the batch take parks at once
 * on an empty input (see {@link MemorySourceNoSpinParkWakeStress}); it must return with the value
 * once it is published. A lost wake-up parks it for ever: STALE.
 */
@JCStressTest(Mode.Termination)
@Description("batch take (no spin, no yield) vs publish(1): the batch always returns with 1")
@Outcome(id = "TERMINATED", expect = ACCEPTABLE, desc = "the publish woke the batch take")
@Outcome(id = "ERROR", expect = FORBIDDEN, desc = "the batch threw, or took anything but 1")
@Outcome(id = "STALE", expect = FORBIDDEN, desc = "lost wake-up: the batch take never returned")
@State
public class MemorySourceNoSpinBatchParkWakeStress {
  private final MemorySource<Integer> source = StressSources.parkingSource(4);

  @SuppressWarnings("unchecked")
  private final BatchReader<Integer> input =
      (BatchReader<Integer>) source.serviceInput("stress-service");

  /** The service's batch take. */
  @Actor
  public void service() throws InterruptedException {
    input.takeAvailable(
        value -> {
          if (value != 1) {
            throw new IllegalStateException("took " + value + ", the only value published was 1");
          }
          return true;
        });
  }

  /** The publisher. */
  @Signal
  public void publisher() {
    source.publish(1);
  }
}

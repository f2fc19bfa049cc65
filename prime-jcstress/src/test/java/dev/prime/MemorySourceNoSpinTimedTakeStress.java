package dev.prime;

import static org.openjdk.jcstress.annotations.Expect.ACCEPTABLE;
import static org.openjdk.jcstress.annotations.Expect.FORBIDDEN;

import org.openjdk.jcstress.annotations.Actor;
import org.openjdk.jcstress.annotations.Description;
import org.openjdk.jcstress.annotations.JCStressTest;
import org.openjdk.jcstress.annotations.Outcome;
import org.openjdk.jcstress.annotations.State;
import org.openjdk.jcstress.infra.results.I_Result;

/**
 * Park and wake of a timed take with no waiting budget: a take with a bound on an empty source
 * whose readers neither spin nor yield registers as a sleeper and parks until its deadline at
 * once, so the publish lands between the registration and the timed park, or during it, in most
 * samples. It must return the value as soon as it is published: a take woken only by its 10 s
 * deadline is {@code -8} (a lost wake-up that the deadline's last look hides), one that got
 * nothing is {@code 0}.
 */
@JCStressTest
@Description("timed take (no spin, no yield) vs publish(1): the take gets 1 before its bound")
@Outcome(id = "1", expect = ACCEPTABLE, desc = "the publish woke the timed take")
@Outcome(expect = FORBIDDEN, desc = "not woken (-8), nothing taken (0) or a wrong value")
@State
public class MemorySourceNoSpinTimedTakeStress {
  private final MemorySource<Integer> source = StressSources.parkingSource(4);
  private final Reader<Integer> reader = source.reader();

  /** The reader. */
  @Actor
  public void reader(I_Result r) {
    r.r1 = StressSources.take(reader);
  }

  /** The publisher. */
  @Actor
  public void publisher() {
    source.publish(1);
  }
}

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
 * One publisher publishes 1 then 2 while a reader takes twice (each take bounded: 0 if it waited
 * {@link StressSources#BOUND}, -8 if the value came only at that deadline). A take that finds nothing spins, then parks; the publish must wake
 * it, and both values arrive in order.
 */
@JCStressTest
@Description("publish(1), publish(2) vs take, take: exactly 1 then 2")
@Outcome(id = "1, 2", expect = ACCEPTABLE, desc = "both values, in order")
@Outcome(expect = FORBIDDEN, desc = "reordered, duplicated, lost, or a take not woken")
@State
public class MemorySourceTakeStress {
  private final MemorySource<Integer> source = StressSources.source(4);
  private final Reader<Integer> reader = source.reader();

  /** The publisher. */
  @Actor
  public void publisher() {
    source.publish(1);
    source.publish(2);
  }

  /** The reader. */
  @Actor
  public void reader(II_Result r) {
    r.r1 = StressSources.take(reader);
    r.r2 = StressSources.take(reader);
  }
}

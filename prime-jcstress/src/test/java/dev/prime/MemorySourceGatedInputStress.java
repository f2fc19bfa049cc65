package dev.prime;

import static org.openjdk.jcstress.annotations.Expect.ACCEPTABLE;
import static org.openjdk.jcstress.annotations.Expect.FORBIDDEN;

import org.openjdk.jcstress.annotations.Actor;
import org.openjdk.jcstress.annotations.Description;
import org.openjdk.jcstress.annotations.JCStressTest;
import org.openjdk.jcstress.annotations.Outcome;
import org.openjdk.jcstress.annotations.State;
import org.openjdk.jcstress.infra.results.III_Result;

/**
 * A service's input gates the publisher: with room for one value, publish(2) waits until the
 * service has taken 1, so the service reads 1 then 2 and misses nothing, where a plain reader
 * would be lapped. Result: first take, second take (0: waited {@link StressSources#BOUND}, -8:
 * woken only by that deadline),
 * missed.
 */
@JCStressTest
@Description("publish(1), publish(2) into a ring of 1 vs a service input's take, take: no miss")
@Outcome(id = "1, 2, 0", expect = ACCEPTABLE, desc = "the publisher waited for the service")
@Outcome(expect = FORBIDDEN, desc = "the service was lapped, or a publish refused or not woken")
@State
public class MemorySourceGatedInputStress {
  private final MemorySource<Integer> source = StressSources.source(1);
  private final Reader<Integer> input = source.serviceInput("stress-service");

  /** The publisher. */
  @Actor
  public void publisher() {
    source.publish(1);
    source.publish(2);
  }

  /** The service. */
  @Actor
  public void service(III_Result r) {
    r.r1 = StressSources.take(input);
    r.r2 = StressSources.take(input);
    r.r3 = (int) input.missed();
  }
}

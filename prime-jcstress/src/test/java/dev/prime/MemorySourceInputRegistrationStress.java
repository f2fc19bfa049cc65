package dev.prime;

import static org.openjdk.jcstress.annotations.Expect.ACCEPTABLE;
import static org.openjdk.jcstress.annotations.Expect.FORBIDDEN;

import java.util.List;
import org.openjdk.jcstress.annotations.Actor;
import org.openjdk.jcstress.annotations.Description;
import org.openjdk.jcstress.annotations.JCStressTest;
import org.openjdk.jcstress.annotations.Outcome;
import org.openjdk.jcstress.annotations.State;
import org.openjdk.jcstress.infra.results.III_Result;

/**
 * A service input opened while the single publisher publishes: the registration takes the
 * publishers' token, so the input starts at the oldest value still retained and the publisher,
 * which from then on respects it, never overwrites a value the input has not read. One publisher
 * publishes 1, 2, 3 into a ring of 2 while another thread opens a service input, drains it and
 * closes it (so the publisher goes on). The input sees a gap-free run from where it started:
 * 1 if it opened before 3 was published, else 2; and misses nothing.
 *
 * <p>Result: the first and last value drained (0, 0: none yet), the input's missed count.
 */
@JCStressTest
@Description("publish 1..3 into a ring of 2 vs serviceInput(), drain, close: gap-free, no miss")
@Outcome(id = "0, 0, 0", expect = ACCEPTABLE, desc = "opened and drained before the first publish")
@Outcome(id = "1, 1, 0", expect = ACCEPTABLE, desc = "1")
@Outcome(id = "1, 2, 0", expect = ACCEPTABLE, desc = "1, 2")
@Outcome(id = "1, 3, 0", expect = ACCEPTABLE, desc = "1, 2, 3")
@Outcome(id = "2, 2, 0", expect = ACCEPTABLE, desc = "opened after 3 was published: 2")
@Outcome(id = "2, 3, 0", expect = ACCEPTABLE, desc = "opened after 3 was published: 2, 3")
@Outcome(expect = FORBIDDEN, desc = "a gap, a value overwritten before it was read, or a miss")
@State
public class MemorySourceInputRegistrationStress {
  private final MemorySource<Integer> source = StressSources.source(2);

  /** The publisher. */
  @Actor
  public void publisher() {
    for (int value = 1; value <= 3; value++) {
      source.publish(value);
    }
  }

  /** Opens a service input, drains what it holds, and closes it. */
  @Actor
  public void service(III_Result r) {
    Reader<Integer> input = source.serviceInput("stress-service");
    List<Integer> values = input.drain();
    r.r3 = (int) input.missed();
    input.close();
    boolean gapFree = true;
    for (int i = 1; i < values.size(); i++) {
      gapFree &= values.get(i) == values.get(i - 1) + 1;
    }
    r.r1 = values.isEmpty() ? 0 : gapFree ? values.get(0) : -1;
    r.r2 = values.isEmpty() ? 0 : values.get(values.size() - 1);
  }
}

package dev.prime;

import static org.openjdk.jcstress.annotations.Expect.ACCEPTABLE;
import static org.openjdk.jcstress.annotations.Expect.ACCEPTABLE_INTERESTING;
import static org.openjdk.jcstress.annotations.Expect.FORBIDDEN;

import org.openjdk.jcstress.annotations.Actor;
import org.openjdk.jcstress.annotations.Description;
import org.openjdk.jcstress.annotations.JCStressTest;
import org.openjdk.jcstress.annotations.Outcome;
import org.openjdk.jcstress.annotations.State;
import org.openjdk.jcstress.infra.results.III_Result;

/**
 * Lap overrun: the ring keeps 2 values and one publisher publishes 1, 2, 3, 4 (sequence n holds
 * n + 1) while a plain reader polls twice, then asks how many it missed. Values come in order,
 * each read value is one the ring still held, and the missed count is exact: the last value read
 * equals the values read plus the values missed. A slot overwritten while the reader read it
 * (a torn or old value) shows as a value that breaks this sum, or as 1 after 3 was published.
 *
 * <p>Result: first poll, second poll (0: nothing new), missed.
 */
@JCStressTest
@Description("publish 1..4 into a ring of 2 vs poll, poll, missed(): in order, missed exact")
@Outcome(id = "0, 0, 0", expect = ACCEPTABLE, desc = "polled before the first publish")
@Outcome(id = "0, 1, 0", expect = ACCEPTABLE, desc = "1, nothing missed")
@Outcome(id = "0, 2, 1", expect = ACCEPTABLE_INTERESTING, desc = "lapped once: 1 missed, then 2")
@Outcome(id = "0, 3, 2", expect = ACCEPTABLE_INTERESTING, desc = "lapped: 1, 2 missed, then 3")
@Outcome(id = "1, 0, 0", expect = ACCEPTABLE, desc = "1, then nothing new")
@Outcome(id = "1, 2, 0", expect = ACCEPTABLE, desc = "1, 2, nothing missed")
@Outcome(id = "1, 3, 1", expect = ACCEPTABLE_INTERESTING, desc = "1, lapped: 2 missed, then 3")
@Outcome(id = "2, 0, 1", expect = ACCEPTABLE_INTERESTING, desc = "lapped: 1 missed, 2, nothing new")
@Outcome(id = "2, 3, 1", expect = ACCEPTABLE_INTERESTING, desc = "lapped: 1 missed, 2, 3")
@Outcome(id = "3, 4, 2", expect = ACCEPTABLE_INTERESTING, desc = "lapped: 1, 2 missed, 3, 4")
@Outcome(expect = FORBIDDEN, desc = "out of order, a value the ring no longer held, or a wrong count")
@State
public class MemorySourceLapStress {
  private final MemorySource<Integer> source = StressSources.source(2);
  private final Reader<Integer> reader = source.reader();

  /** The publisher, lapping the reader. */
  @Actor
  public void publisher() {
    for (int value = 1; value <= 4; value++) {
      source.publish(value);
    }
  }

  /** The reader. */
  @Actor
  public void reader(III_Result r) {
    r.r1 = reader.poll().orElse(0);
    r.r2 = reader.poll().orElse(0);
    r.r3 = (int) reader.missed();
  }
}

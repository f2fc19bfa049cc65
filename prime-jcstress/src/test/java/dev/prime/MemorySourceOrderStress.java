package dev.prime;

import static org.openjdk.jcstress.annotations.Expect.ACCEPTABLE;
import static org.openjdk.jcstress.annotations.Expect.ACCEPTABLE_INTERESTING;
import static org.openjdk.jcstress.annotations.Expect.FORBIDDEN;

import org.openjdk.jcstress.annotations.Actor;
import org.openjdk.jcstress.annotations.Description;
import org.openjdk.jcstress.annotations.JCStressTest;
import org.openjdk.jcstress.annotations.Outcome;
import org.openjdk.jcstress.annotations.State;
import org.openjdk.jcstress.infra.results.II_Result;

/**
 * One publisher publishes 1 then 2; a reader opened before polls twice (0: nothing yet). The
 * reader sees a prefix of the publisher's order: never 2 before 1, never a value twice, never 2
 * without 1 (the ring keeps 4, so nothing is missed).
 */
@JCStressTest
@Description("publish(1), publish(2) vs poll, poll: a prefix in order, no duplicate, no gap")
@Outcome(id = "0, 0", expect = ACCEPTABLE, desc = "both polls before the first publish")
@Outcome(id = "0, 1", expect = ACCEPTABLE, desc = "the second poll sees 1")
@Outcome(id = "1, 0", expect = ACCEPTABLE, desc = "1, then nothing new yet")
@Outcome(id = "1, 2", expect = ACCEPTABLE_INTERESTING, desc = "both, in order")
@Outcome(expect = FORBIDDEN, desc = "reordered, duplicated or skipped a retained value")
@State
public class MemorySourceOrderStress {
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
    r.r1 = reader.poll().orElse(0);
    r.r2 = reader.poll().orElse(0);
  }
}

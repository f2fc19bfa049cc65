package dev.prime;

import static org.openjdk.jcstress.annotations.Expect.ACCEPTABLE;
import static org.openjdk.jcstress.annotations.Expect.ACCEPTABLE_INTERESTING;
import static org.openjdk.jcstress.annotations.Expect.FORBIDDEN;

import org.openjdk.jcstress.annotations.Actor;
import org.openjdk.jcstress.annotations.Description;
import org.openjdk.jcstress.annotations.JCStressTest;
import org.openjdk.jcstress.annotations.Outcome;
import org.openjdk.jcstress.annotations.State;
import org.openjdk.jcstress.infra.results.I_Result;

/**
 * Publish then close, against a bounded take: the take either gets the value (it read it before
 * the close) or ends with {@link CoreClosedException}; it never times out, and never sees anything
 * but the one value published.
 *
 * <p>Result: 1 (the value), -1 (CoreClosedException), 0 (waited {@link StressSources#BOUND}), -8 (woken
 * only by that deadline).
 */
@JCStressTest
@Description("publish(1), close() vs take(bound): the value or CoreClosedException, never a hang")
@Outcome(id = "1", expect = ACCEPTABLE, desc = "took the value before the close")
@Outcome(id = "-1", expect = ACCEPTABLE_INTERESTING, desc = "the close ended the take")
@Outcome(id = "0", expect = FORBIDDEN, desc = "the take missed both the value and the close")
@Outcome(expect = FORBIDDEN, desc = "a value nobody published")
@State
public class MemorySourcePublishCloseTakeStress {
  private final MemorySource<Integer> source = StressSources.source(4);
  private final Reader<Integer> reader = source.reader();

  /** Publishes, then closes. */
  @Actor
  public void publisherThenCloser() {
    source.publish(1);
    source.close();
  }

  /** The taker. */
  @Actor
  public void taker(I_Result r) {
    r.r1 = StressSources.take(reader);
  }
}

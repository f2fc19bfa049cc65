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
 * Close during take: an untimed {@code take} on an empty source ends with {@link
 * CoreClosedException} when the source closes, wherever the close lands. A take that misses the
 * close parks for ever, which jcstress reports as STALE.
 */
@JCStressTest(Mode.Termination)
@Description("take() vs close(): the take ends with CoreClosedException")
@Outcome(id = "TERMINATED", expect = ACCEPTABLE, desc = "the take saw the close")
@Outcome(id = "ERROR", expect = FORBIDDEN, desc = "the take returned a value, or threw otherwise")
@Outcome(id = "STALE", expect = FORBIDDEN, desc = "the take missed the close and hangs")
@State
public class MemorySourceCloseDuringTakeStress {
  private final MemorySource<Integer> source = StressSources.source(4);
  private final Reader<Integer> reader = source.reader();

  /** The taker: nothing is ever published, so only the close can end it. */
  @Actor
  public void taker() throws InterruptedException {
    try {
      Integer value = reader.take();
      throw new IllegalStateException("took " + value + " from a source nothing was published to");
    } catch (CoreClosedException expected) {
      // the promised end
    }
  }

  /** Closes the source. */
  @Signal
  public void closer() {
    source.close();
  }
}

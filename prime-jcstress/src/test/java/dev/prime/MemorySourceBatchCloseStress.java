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
 * Close during a batch take: a service input's {@link BatchReader#takeAvailable} on an empty
 * source ends with {@link CoreClosedException} when the source closes, wherever the close lands.
 * A batch take that misses the close parks for ever: STALE.
 */
@JCStressTest(Mode.Termination)
@Description("batch take vs close(): the batch ends with CoreClosedException")
@Outcome(id = "TERMINATED", expect = ACCEPTABLE, desc = "the batch take saw the close")
@Outcome(id = "ERROR", expect = FORBIDDEN, desc = "the batch handed out a value, or threw otherwise")
@Outcome(id = "STALE", expect = FORBIDDEN, desc = "the batch take missed the close and hangs")
@State
public class MemorySourceBatchCloseStress {
  private final MemorySource<Integer> source = StressSources.source(4);

  @SuppressWarnings("unchecked")
  private final BatchReader<Integer> input =
      (BatchReader<Integer>) source.serviceInput("stress-service");

  /** The service's batch take: nothing is ever published, so only the close can end it. */
  @Actor
  public void service() throws InterruptedException {
    try {
      input.takeAvailable(
          value -> {
            throw new IllegalStateException("took " + value + " from a source nothing was published to");
          });
      throw new IllegalStateException("the batch take returned without a value");
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

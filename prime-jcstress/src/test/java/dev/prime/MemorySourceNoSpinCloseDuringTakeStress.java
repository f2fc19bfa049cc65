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
 * Close during a take with no waiting budget: the untimed take parks at once on an empty source
 * (see {@link MemorySourceNoSpinParkWakeStress}); closing the source must wake it, and it must end
 * with {@link CoreClosedException}. A close that does not wake it leaves it parked for ever: STALE.
 */
@JCStressTest(Mode.Termination)
@Description("untimed take (no spin, no yield) vs close(): the take ends with CoreClosedException")
@Outcome(id = "TERMINATED", expect = ACCEPTABLE, desc = "the close woke the take, which ended")
@Outcome(id = "ERROR", expect = FORBIDDEN, desc = "the take returned or threw anything else")
@Outcome(id = "STALE", expect = FORBIDDEN, desc = "lost wake-up: the take never ended")
@State
public class MemorySourceNoSpinCloseDuringTakeStress {
  private final MemorySource<Integer> source = StressSources.parkingSource(4);
  private final Reader<Integer> reader = source.reader();

  /** The reader. */
  @Actor
  public void reader() throws InterruptedException {
    try {
      Integer value = reader.take();
      throw new IllegalStateException("took " + value + " from a source nobody published to");
    } catch (CoreClosedException expected) {
      // the source closed: how a take ends
    }
  }

  /** The closer. */
  @Signal
  public void closer() {
    source.close();
  }
}

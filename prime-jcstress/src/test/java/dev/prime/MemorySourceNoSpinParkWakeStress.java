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
 * Park and wake with no waiting budget: an untimed take on an empty source whose readers neither
 * spin nor yield registers as a sleeper and parks at once, so the publish lands between the
 * registration and the park, or during the park, in most samples (with the standard budget it
 * mostly lands while the reader still spins). It must return with the value; a lost wake-up parks
 * it for ever: STALE.
 */
@JCStressTest(Mode.Termination)
@Description("untimed take (no spin, no yield) vs publish(1): the take always returns")
@Outcome(id = "TERMINATED", expect = ACCEPTABLE, desc = "the publish woke the take")
@Outcome(id = "ERROR", expect = FORBIDDEN, desc = "the take threw, or took anything but 1")
@Outcome(id = "STALE", expect = FORBIDDEN, desc = "lost wake-up: the take never returned")
@State
public class MemorySourceNoSpinParkWakeStress {
  private final MemorySource<Integer> source = StressSources.parkingSource(4);
  private final Reader<Integer> reader = source.reader();

  /** The reader. */
  @Actor
  public void reader() throws InterruptedException {
    int value = reader.take();
    if (value != 1) {
      throw new IllegalStateException("took " + value + ", the only value published was 1");
    }
  }

  /** The publisher. */
  @Signal
  public void publisher() {
    source.publish(1);
  }
}

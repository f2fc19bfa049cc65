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
 * Park and wake: an untimed {@code take} on an empty source (it spins, then parks on the lock's
 * condition) must return once a value is published, wherever the publish lands: before the take,
 * during its spin, between its last look and its park, or while it is parked. A lost wake-up
 * leaves the take parked for ever, which jcstress reports as STALE.
 */
@JCStressTest(Mode.Termination)
@Description("take() vs publish(1): the take always returns")
@Outcome(id = "TERMINATED", expect = ACCEPTABLE, desc = "the publish woke the take")
@Outcome(id = "ERROR", expect = FORBIDDEN, desc = "the take threw, or took a value never published")
@Outcome(id = "STALE", expect = FORBIDDEN, desc = "lost wake-up: the take never returned")
@State
public class MemorySourceParkWakeStress {
  private final MemorySource<Integer> source = StressSources.source(4);
  private final Reader<Integer> reader = source.reader();

  /** The taker; it must see 1. */
  @Actor
  public void taker() throws InterruptedException {
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

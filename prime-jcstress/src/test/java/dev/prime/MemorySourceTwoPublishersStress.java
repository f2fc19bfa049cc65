package dev.prime;

import static org.openjdk.jcstress.annotations.Expect.ACCEPTABLE;
import static org.openjdk.jcstress.annotations.Expect.FORBIDDEN;

import java.util.List;
import org.openjdk.jcstress.annotations.Actor;
import org.openjdk.jcstress.annotations.Arbiter;
import org.openjdk.jcstress.annotations.Description;
import org.openjdk.jcstress.annotations.JCStressTest;
import org.openjdk.jcstress.annotations.Outcome;
import org.openjdk.jcstress.annotations.State;
import org.openjdk.jcstress.infra.results.LL_Result;

/**
 * Two publishers, each polling its own reader right after publishing (the multi-publisher path:
 * they serialise on the source's lock). A broadcast source has one order: every reader reads the
 * same sequence, each value once.
 */
@JCStressTest
@Description("publish(1) vs publish(2), two readers: both read one and the same order")
@Outcome(id = "12, 12", expect = ACCEPTABLE, desc = "1 went first; both readers agree")
@Outcome(id = "21, 21", expect = ACCEPTABLE, desc = "2 went first; both readers agree")
@Outcome(expect = FORBIDDEN, desc = "readers disagree, or a value lost or duplicated")
@State
public class MemorySourceTwoPublishersStress {
  private final MemorySource<Integer> source = StressSources.source(4);
  private final Reader<Integer> first = source.reader();
  private final Reader<Integer> second = source.reader();
  private final StringBuilder firstRead = new StringBuilder();
  private final StringBuilder secondRead = new StringBuilder();

  /** Publishes 1, then reads what the first reader has. */
  @Actor
  public void publishOne() {
    source.publish(1);
    first.poll().ifPresent(firstRead::append);
  }

  /** Publishes 2, then reads what the second reader has. */
  @Actor
  public void publishTwo() {
    source.publish(2);
    second.poll().ifPresent(secondRead::append);
  }

  /** Reads the rest once both are done. */
  @Arbiter
  public void rest(LL_Result r) {
    List<Integer> firstRest = first.drain();
    List<Integer> secondRest = second.drain();
    firstRest.forEach(firstRead::append);
    secondRest.forEach(secondRead::append);
    r.r1 = firstRead.toString();
    r.r2 = secondRead.toString();
  }
}

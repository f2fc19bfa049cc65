package dev.prime;

import static org.openjdk.jcstress.annotations.Expect.ACCEPTABLE;
import static org.openjdk.jcstress.annotations.Expect.FORBIDDEN;

import org.openjdk.jcstress.annotations.Actor;
import org.openjdk.jcstress.annotations.Description;
import org.openjdk.jcstress.annotations.JCStressTest;
import org.openjdk.jcstress.annotations.Outcome;
import org.openjdk.jcstress.annotations.State;
import org.openjdk.jcstress.infra.results.II_Result;

/**
 * One reader shared by two threads, which the reader's lock-free cursor (a compare-and-set per
 * value) must allow: with 1 and 2 published, two threads poll the same reader at once. Each
 * value goes to exactly one of them.
 *
 * <p>Result: what each thread polled (0: nothing).
 */
@JCStressTest
@Description("1, 2 published; poll ∥ poll on one reader: each value to exactly one caller")
@Outcome(id = "1, 2", expect = ACCEPTABLE, desc = "the first thread polled first")
@Outcome(id = "2, 1", expect = ACCEPTABLE, desc = "the second thread polled first")
@Outcome(expect = FORBIDDEN, desc = "a value taken twice, or one taken by nobody")
@State
public class MemorySourceSharedReaderStress {
  private final MemorySource<Integer> source = StressSources.source(4);
  private final Reader<Integer> reader = source.reader();

  /** Publishes 1 and 2 before the threads poll. */
  public MemorySourceSharedReaderStress() {
    source.publish(1);
    source.publish(2);
  }

  /** One thread of the reader. */
  @Actor
  public void first(II_Result r) {
    r.r1 = reader.poll().orElse(0);
  }

  /** The other thread of the reader. */
  @Actor
  public void second(II_Result r) {
    r.r2 = reader.poll().orElse(0);
  }
}

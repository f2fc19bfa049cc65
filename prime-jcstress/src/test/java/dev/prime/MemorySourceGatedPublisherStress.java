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
 * A publisher waiting for room in a service's input (ring of 1, the service never takes) is
 * released by the other party, never left to its timeout: closing the service's input (the
 * service stopped) lets publish(2) through; closing the source ends it with {@link
 * CoreClosedException}. Neither may end in {@link QueueFullException}, which comes only after
 * {@link StressSources#BOUND}.
 *
 * <p>Result per publish: 1 published, -1 CoreClosedException, -2 QueueFullException. The test's
 * two variants are the two {@code *Stress} classes nested here.
 */
public final class MemorySourceGatedPublisherStress {
  private MemorySourceGatedPublisherStress() {}

  private static int publish(MemorySource<Integer> source, int value) {
    try {
      source.publish(value);
      return 1;
    } catch (CoreClosedException e) {
      return -1;
    } catch (QueueFullException e) {
      return -2;
    }
  }

  /** Closing the service's input releases the waiting publisher. */
  @JCStressTest
  @Description("publish(1), publish(2) into a ring of 1 gated by an idle service vs input.close()")
  @Outcome(id = "1, 1", expect = ACCEPTABLE, desc = "the input's close let publish(2) through")
  @Outcome(expect = FORBIDDEN, desc = "a publish refused: the closed input still gated")
  @State
  public static class InputClosedStress {
    private final MemorySource<Integer> source = StressSources.source(1);
    private final Reader<Integer> input = source.serviceInput("stress-service");

    /** The publisher. */
    @Actor
    public void publisher(II_Result r) {
      r.r1 = publish(source, 1);
      r.r2 = publish(source, 2);
    }

    /** The service stops. */
    @Actor
    public void serviceStops() {
      input.close();
    }
  }

  /** Closing the source ends the waiting publisher with CoreClosedException. */
  @JCStressTest
  @Description("publish(1), publish(2) into a ring of 1 gated by an idle service vs source.close()")
  @Outcome(id = "1, -1", expect = ACCEPTABLE, desc = "1 published; the close ended publish(2)")
  @Outcome(id = "-1, -1", expect = ACCEPTABLE_INTERESTING, desc = "closed before either publish")
  @Outcome(expect = FORBIDDEN, desc = "published past an unread value, or refused for a full queue")
  @State
  public static class SourceClosedStress {
    private final MemorySource<Integer> source = StressSources.source(1);

    {
      source.serviceInput("stress-service"); // never takes
    }

    /** The publisher. */
    @Actor
    public void publisher(II_Result r) {
      r.r1 = publish(source, 1);
      r.r2 = r.r1 == 1 ? publish(source, 2) : -1;
    }

    /** The core closes. */
    @Actor
    public void closer() {
      source.close();
    }
  }
}

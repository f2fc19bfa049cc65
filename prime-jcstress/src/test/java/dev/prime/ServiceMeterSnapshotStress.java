package dev.prime;

import static org.openjdk.jcstress.annotations.Expect.ACCEPTABLE;
import static org.openjdk.jcstress.annotations.Expect.FORBIDDEN;

import dev.prime.internal.RateLimitedLog;
import org.openjdk.jcstress.annotations.Actor;
import org.openjdk.jcstress.annotations.Description;
import org.openjdk.jcstress.annotations.JCStressTest;
import org.openjdk.jcstress.annotations.Outcome;
import org.openjdk.jcstress.annotations.State;
import org.openjdk.jcstress.infra.results.IIII_Result;

/**
 * A node's meter ({@link ServiceMeter}) counts a value in, then its processing (timed, failed),
 * then its output, while a snapshot is read on another thread. {@link ServiceMetrics} promises
 * that a value in flight may show in {@code valuesIn} and not yet in the others: never the
 * reverse, a value counted out, failed or timed that the same snapshot does not count in.
 */
@JCStressTest
@Description("in(), processed(failed), out() vs snapshot(): nothing out, failed or timed that is not in")
@Outcome(id = "0, 0, 0, 0", expect = ACCEPTABLE, desc = "the snapshot came first")
@Outcome(
    id = {"1, 0, 0, 0", "1, 1, 0, 0", "1, 1, 1, 0", "1, 0, 1, 0", "1, 0, 0, 1", "1, 1, 0, 1",
      "1, 0, 1, 1", "1, 1, 1, 1"},
    expect = ACCEPTABLE,
    desc = "in, and whatever of its processing and output the snapshot read")
@Outcome(expect = FORBIDDEN, desc = "a value counted out, failed or timed, not in")
@State
public class ServiceMeterSnapshotStress {
  private final ServiceMeter meter =
      new ServiceMeter("chain", "BlockChain", new RateLimitedLog(ServiceMeterSnapshotStress.class.getName()));

  /** A service's taps around one value whose logic threw and still gave an output. */
  @Actor
  public void service() {
    meter.in();
    meter.processed(1, true);
    meter.out();
  }

  /** A snapshot: in, timed, failed, out. */
  @Actor
  public void snapshot(IIII_Result r) {
    ServiceMetrics metrics = meter.snapshot(null, 0, -1, 0);
    r.r1 = (int) metrics.valuesIn();
    r.r2 = (int) metrics.processing().count();
    r.r3 = (int) metrics.failures();
    r.r4 = (int) metrics.valuesOut();
  }
}

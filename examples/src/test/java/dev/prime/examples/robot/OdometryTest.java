package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;

import org.junit.jupiter.api.Test;

/** A block is a plain object: construct it, call process, check the output. No core needed. */
class OdometryTest {
  private static final RobotSpec SPEC = RobotSpec.SMALL_INDOOR;
  private static final double DT = 0.01;
  private static final long TICKS_PER_METRE = Math.round(1 / SPEC.metresPerTick());

  @Test
  void firstReadingSetsTheBaselineAndReportsTheStartPose() {
    Odometry odometry = new Odometry(SPEC, DT, new Pose(1, 2, 0.5));

    Estimate estimate = odometry.process(new EncoderReading(7, 1000, -1000));

    assertEquals(new Estimate(7, new Pose(1, 2, 0.5), WheelSpeeds.STILL), estimate);
  }

  @Test
  void equalTicksOnBothWheelsDriveStraightAlongTheHeading() {
    Odometry odometry = new Odometry(SPEC, DT, Pose.ORIGIN);
    odometry.process(new EncoderReading(0, 0, 0));

    Estimate estimate = odometry.process(new EncoderReading(100, TICKS_PER_METRE, TICKS_PER_METRE));

    assertEquals(1.0, estimate.pose().x(), 1e-3);
    assertEquals(0.0, estimate.pose().y(), 1e-12);
    assertEquals(0.0, estimate.pose().heading(), 1e-12);
    // one metre in 100 steps of 10 ms: 1 m/s on each wheel
    assertEquals(1.0, estimate.measured().left(), 1e-3);
    assertEquals(1.0, estimate.measured().right(), 1e-3);
  }

  @Test
  void oppositeTicksTurnOnTheSpot() {
    Odometry odometry = new Odometry(SPEC, DT, Pose.ORIGIN);
    odometry.process(new EncoderReading(0, 0, 0));
    // a quarter turn: each rim rolls a quarter of the circle whose diameter is the track
    double rim = Math.PI * SPEC.trackWidth() / 4;
    long ticks = Math.round(rim / SPEC.metresPerTick());

    Estimate estimate = odometry.process(new EncoderReading(1, -ticks, ticks));

    assertEquals(Math.PI / 2, estimate.pose().heading(), 1e-2);
    assertEquals(0.0, estimate.pose().x(), 1e-12);
    assertEquals(0.0, estimate.pose().y(), 1e-12);
  }

  @Test
  void integratesAcrossReadings() {
    Odometry odometry = new Odometry(SPEC, DT, Pose.ORIGIN);
    odometry.process(new EncoderReading(0, 0, 0));
    odometry.process(new EncoderReading(1, TICKS_PER_METRE, TICKS_PER_METRE));

    Estimate estimate =
        odometry.process(new EncoderReading(2, 2 * TICKS_PER_METRE, 2 * TICKS_PER_METRE));

    assertEquals(2.0, estimate.pose().x(), 2e-3);
    assertEquals(2, estimate.step());
  }

  @Test
  void rejectsReadingsOutOfOrderWithAClearMessage() {
    Odometry odometry = new Odometry(SPEC, DT, Pose.ORIGIN);
    odometry.process(new EncoderReading(5, 0, 0));

    IllegalArgumentException e =
        assertThrows(
            IllegalArgumentException.class,
            () -> odometry.process(new EncoderReading(5, 10, 10)));
    assertEquals(
        "encoder readings must come in step order: got step 5 after step 5", e.getMessage());
  }
}

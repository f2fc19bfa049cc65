package dev.prime.examples.robot;

import dev.prime.Block;
import java.util.Objects;

/**
 * Dead reckoning: turns encoder counts into a pose and measured wheel speeds.
 *
 * <p>A plain block that keeps the last counts and pose between calls, so one instance serves one
 * stream of readings in order (in the robot it backs one service). The first reading only sets the
 * baseline.
 */
public final class Odometry implements Block<EncoderReading, Estimate> {
  private final RobotSpec spec;
  private final double dt;
  private Pose pose;
  private EncoderReading last;

  /**
   * @param spec the robot's geometry
   * @param dt seconds between two simulation steps
   * @param start the pose at the first reading
   */
  public Odometry(RobotSpec spec, double dt, Pose start) {
    this.spec = Objects.requireNonNull(spec, "spec must not be null");
    this.pose = Objects.requireNonNull(start, "start pose must not be null");
    if (!(dt > 0)) {
      throw new IllegalArgumentException("dt must be positive seconds, was " + dt);
    }
    this.dt = dt;
  }

  @Override
  public Estimate process(EncoderReading reading) {
    if (last == null) {
      last = reading;
      return new Estimate(reading.step(), pose, WheelSpeeds.STILL);
    }
    long steps = reading.step() - last.step();
    if (steps <= 0) {
      throw new IllegalArgumentException(
          "encoder readings must come in step order: got step " + reading.step()
              + " after step " + last.step());
    }
    double left = (reading.leftTicks() - last.leftTicks()) * spec.metresPerTick();
    double right = (reading.rightTicks() - last.rightTicks()) * spec.metresPerTick();
    pose = pose.drive(left, right, spec.trackWidth());
    last = reading;
    double elapsed = steps * dt;
    return new Estimate(reading.step(), pose, new WheelSpeeds(left / elapsed, right / elapsed));
  }
}

package dev.prime.examples.robot;

import dev.prime.Block;
import java.util.Objects;

/**
 * Go-to-goal steering: turns toward the goal and drives at a speed that shrinks near it.
 *
 * <p>A stateless plain block: the forward speed is proportional to the distance (capped) and
 * scaled down while the robot faces away; the turn rate is proportional to the heading error
 * (capped). The result is converted to rim speeds of the two wheels.
 */
public final class GoalPlanner implements Block<Estimate, Setpoint> {
  /** Forward speed per metre of distance, 1/s. */
  static final double DISTANCE_GAIN = 0.8;
  /** Turn rate per radian of heading error, 1/s. */
  static final double HEADING_GAIN = 3.0;
  /** Top forward speed, m/s. */
  static final double MAX_SPEED = 0.5;
  /** Top turn rate, rad/s. */
  static final double MAX_TURN_RATE = 2.0;

  private final Goal goal;
  private final RobotSpec spec;

  /**
   * @param goal where to drive
   * @param spec the robot's geometry
   */
  public GoalPlanner(Goal goal, RobotSpec spec) {
    this.goal = Objects.requireNonNull(goal, "goal must not be null");
    this.spec = Objects.requireNonNull(spec, "spec must not be null");
  }

  @Override
  public Setpoint process(Estimate estimate) {
    Pose pose = estimate.pose();
    double distance = pose.distanceTo(goal);
    double bearing = Math.atan2(goal.y() - pose.y(), goal.x() - pose.x());
    double headingError = Pose.normalize(bearing - pose.heading());
    double facing = Math.max(0, Math.cos(headingError));
    double speed = Math.min(MAX_SPEED, DISTANCE_GAIN * distance) * facing;
    double turnRate = clamp(HEADING_GAIN * headingError, MAX_TURN_RATE);
    double half = turnRate * spec.trackWidth() / 2;
    return new Setpoint(estimate, new WheelSpeeds(speed - half, speed + half));
  }

  private static double clamp(double value, double limit) {
    return Math.max(-limit, Math.min(limit, value));
  }
}

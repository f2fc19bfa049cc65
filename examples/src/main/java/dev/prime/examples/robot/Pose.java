package dev.prime.examples.robot;

import java.util.Locale;

/**
 * Where the robot is on the floor.
 *
 * @param x metres
 * @param y metres
 * @param heading radians, counter-clockwise from the x axis, in (-pi, pi]
 */
public record Pose(double x, double y, double heading) {

  /** The pose at the origin, facing along x. */
  public static final Pose ORIGIN = new Pose(0, 0, 0);

  /**
   * The straight-line distance from this pose to a goal.
   *
   * @param goal the goal
   * @return metres
   */
  public double distanceTo(Goal goal) {
    return Math.hypot(goal.x() - x, goal.y() - y);
  }

  /**
   * An angle brought into (-pi, pi].
   *
   * @param radians any angle
   * @return the same direction in (-pi, pi]
   */
  public static double normalize(double radians) {
    double a = Math.IEEEremainder(radians, 2 * Math.PI);
    return a <= -Math.PI ? a + 2 * Math.PI : a;
  }

  @Override
  public String toString() {
    return String.format(
        Locale.ROOT, "(x=%.3f, y=%.3f, heading=%.1f deg)", x, y, Math.toDegrees(heading));
  }
}

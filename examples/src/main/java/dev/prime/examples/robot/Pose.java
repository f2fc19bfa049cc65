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
   * The pose after the wheels of a differential drive travelled the given distances (the
   * midpoint-heading approximation, exact for straight lines and arcs traversed in small steps).
   *
   * @param left metres travelled by the left wheel
   * @param right metres travelled by the right wheel
   * @param trackWidth metres between the wheels
   * @return the new pose
   */
  public Pose drive(double left, double right, double trackWidth) {
    double forward = (left + right) / 2;
    double turn = (right - left) / trackWidth;
    double midHeading = heading + turn / 2;
    return new Pose(
        x + forward * Math.cos(midHeading),
        y + forward * Math.sin(midHeading),
        normalize(heading + turn));
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

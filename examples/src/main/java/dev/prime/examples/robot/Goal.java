package dev.prime.examples.robot;

/**
 * A point the robot must drive to.
 *
 * @param x metres
 * @param y metres
 */
public record Goal(double x, double y) {

  /**
   * Checks the coordinates.
   *
   * @param x metres
   * @param y metres
   * @throws IllegalArgumentException if a coordinate is not a finite number
   */
  public Goal {
    if (!Double.isFinite(x) || !Double.isFinite(y)) {
      throw new IllegalArgumentException(
          "goal coordinates must be finite numbers, were " + x + "," + y);
    }
  }

  @Override
  public String toString() {
    return String.format(java.util.Locale.ROOT, "(x=%.3f, y=%.3f)", x, y);
  }
}

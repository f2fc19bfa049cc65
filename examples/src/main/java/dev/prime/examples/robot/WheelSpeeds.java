package dev.prime.examples.robot;

/**
 * Linear speeds of the two wheels' rims.
 *
 * @param left metres per second, positive forward
 * @param right metres per second, positive forward
 */
public record WheelSpeeds(double left, double right) {

  /** Both wheels still. */
  public static final WheelSpeeds STILL = new WheelSpeeds(0, 0);
}

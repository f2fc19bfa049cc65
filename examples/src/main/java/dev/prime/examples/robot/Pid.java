package dev.prime.examples.robot;

/**
 * A discrete PID controller with output clamping and anti-windup (the integral stops growing
 * while the output is saturated in the same direction). Plain state, one user at a time.
 */
public final class Pid {
  private final double kp;
  private final double ki;
  private final double kd;
  private final double limit;
  private double integral;
  private double previousError;
  private boolean first = true;

  /**
   * @param kp proportional gain
   * @param ki integral gain, per second
   * @param kd derivative gain, seconds
   * @param limit the output is clamped to plus or minus this; positive
   */
  public Pid(double kp, double ki, double kd, double limit) {
    if (!(limit > 0)) {
      throw new IllegalArgumentException("PID output limit must be positive, was " + limit);
    }
    this.kp = kp;
    this.ki = ki;
    this.kd = kd;
    this.limit = limit;
  }

  /**
   * Computes the correction for one step.
   *
   * @param error setpoint minus measurement
   * @param dt seconds since the previous update; positive
   * @param bias added to the output before clamping (feed-forward)
   * @return the clamped output
   */
  public double update(double error, double dt, double bias) {
    if (!(dt > 0)) {
      throw new IllegalArgumentException("PID dt must be positive seconds, was " + dt);
    }
    double derivative = first ? 0 : (error - previousError) / dt;
    first = false;
    previousError = error;
    double candidate = integral + error * dt;
    double output = bias + kp * error + ki * candidate + kd * derivative;
    boolean saturatedUp = output > limit && error > 0;
    boolean saturatedDown = output < -limit && error < 0;
    if (!saturatedUp && !saturatedDown) {
      integral = candidate;
    }
    return Math.max(-limit, Math.min(limit, output));
  }

  /** {@return the accumulated integral of the error, in error-seconds} */
  public double integral() {
    return integral;
  }
}

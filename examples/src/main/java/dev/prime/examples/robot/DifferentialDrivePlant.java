package dev.prime.examples.robot;

import java.util.Objects;

/**
 * The simulated robot: two motors with first-order lag driving two wheels, and the true pose.
 * Each {@link #step} advances simulated time by a fixed {@code dt}; nothing here reads a clock,
 * so a run is the same every time. Not thread-safe: the simulation loop owns it.
 */
public final class DifferentialDrivePlant {
  private final RobotSpec spec;
  private Pose pose;
  private double leftSpeed;
  private double rightSpeed;
  private double leftTravel;
  private double rightTravel;

  /**
   * @param spec the robot
   * @param start its true pose at time zero
   */
  public DifferentialDrivePlant(RobotSpec spec, Pose start) {
    this.spec = Objects.requireNonNull(spec, "spec must not be null");
    this.pose = Objects.requireNonNull(start, "start pose must not be null");
  }

  /**
   * Applies a command for {@code dt} seconds.
   *
   * @param command the motor voltages (clamped to the supply)
   * @param dt seconds; positive
   */
  public void step(DriveCommand command, double dt) {
    if (!(dt > 0)) {
      throw new IllegalArgumentException("dt must be positive seconds, was " + dt);
    }
    leftSpeed = motor(leftSpeed, command.leftVolts(), dt);
    rightSpeed = motor(rightSpeed, command.rightVolts(), dt);
    double left = leftSpeed * dt;
    double right = rightSpeed * dt;
    leftTravel += left;
    rightTravel += right;
    pose = pose.drive(left, right, spec.trackWidth());
  }

  private double motor(double speed, double volts, double dt) {
    double clamped = Math.max(-spec.maxVolts(), Math.min(spec.maxVolts(), volts));
    double steady = clamped * spec.motorGain();
    return steady + (speed - steady) * Math.exp(-dt / spec.motorTimeConstant());
  }

  /** {@return the true pose (which odometry only estimates)} */
  public Pose pose() {
    return pose;
  }

  /** {@return the true rim speeds of the wheels} */
  public WheelSpeeds wheelSpeeds() {
    return new WheelSpeeds(leftSpeed, rightSpeed);
  }

  /** {@return metres the left rim has rolled since time zero (negative if backwards)} */
  public double leftTravel() {
    return leftTravel;
  }

  /** {@return metres the right rim has rolled since time zero (negative if backwards)} */
  public double rightTravel() {
    return rightTravel;
  }
}

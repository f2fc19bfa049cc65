package dev.prime.examples.robot;

import dev.prime.Block;
import java.util.Objects;

/**
 * Wheel speed control: one {@link Pid} per wheel turns the planner's target speeds and the
 * measured speeds into motor voltages, with a feed-forward of the voltage the target needs at
 * steady state. A plain block holding the two controllers' state.
 */
public final class PidMotorController implements Block<Setpoint, DriveCommand> {
  /** Proportional gain, volts per (m/s). */
  static final double KP = 20;
  /** Integral gain, volts per metre. */
  static final double KI = 60;
  /** Derivative gain, volt-seconds per (m/s). */
  static final double KD = 0.02;

  private final RobotSpec spec;
  private final double dt;
  private final Pid left;
  private final Pid right;

  /**
   * @param spec the robot's motors
   * @param dt seconds between two calls
   */
  public PidMotorController(RobotSpec spec, double dt) {
    this.spec = Objects.requireNonNull(spec, "spec must not be null");
    if (!(dt > 0)) {
      throw new IllegalArgumentException("dt must be positive seconds, was " + dt);
    }
    this.dt = dt;
    this.left = new Pid(KP, KI, KD, spec.maxVolts());
    this.right = new Pid(KP, KI, KD, spec.maxVolts());
  }

  @Override
  public DriveCommand process(Setpoint setpoint) {
    WheelSpeeds target = setpoint.target();
    WheelSpeeds measured = setpoint.estimate().measured();
    double leftVolts =
        left.update(target.left() - measured.left(), dt, target.left() / spec.motorGain());
    double rightVolts =
        right.update(target.right() - measured.right(), dt, target.right() / spec.motorGain());
    return new DriveCommand(setpoint.estimate(), target, leftVolts, rightVolts, false);
  }
}

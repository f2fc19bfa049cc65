package dev.prime.examples.robot;

/**
 * The robot's geometry and motors, shared by the simulated plant and the controller blocks.
 *
 * @param wheelRadius metres
 * @param trackWidth distance between the wheels, metres
 * @param ticksPerRevolution encoder ticks per wheel revolution
 * @param motorGain steady-state rim speed per volt, metres per second per volt
 * @param motorTimeConstant how fast a motor follows its voltage, seconds
 * @param maxVolts the supply voltage: commands are clamped to plus or minus this
 */
public record RobotSpec(
    double wheelRadius,
    double trackWidth,
    int ticksPerRevolution,
    double motorGain,
    double motorTimeConstant,
    double maxVolts) {

  /** A small indoor robot: 5 cm wheels, 30 cm track, 1024-tick encoders, 12 V motors. */
  public static final RobotSpec SMALL_INDOOR = new RobotSpec(0.05, 0.30, 1024, 0.2, 0.1, 12);

  /** {@return metres a wheel's rim travels per encoder tick} */
  public double metresPerTick() {
    return 2 * Math.PI * wheelRadius / ticksPerRevolution;
  }
}

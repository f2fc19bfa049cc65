package dev.prime.examples.robot;

/**
 * The voltages for the two motors, with what they were computed from (for the trace).
 *
 * @param estimate the estimate the command answers
 * @param target the wheel speeds the controller aims at
 * @param leftVolts voltage on the left motor
 * @param rightVolts voltage on the right motor
 * @param arrived whether the robot is at its goal (the command then stops the motors)
 */
public record DriveCommand(
    Estimate estimate, WheelSpeeds target, double leftVolts, double rightVolts, boolean arrived) {

  /**
   * The command for a robot at its goal: motors off.
   *
   * @param estimate where the robot is
   * @return a command with zero voltage, marked arrived
   */
  public static DriveCommand stop(Estimate estimate) {
    return new DriveCommand(estimate, WheelSpeeds.STILL, 0, 0, true);
  }
}

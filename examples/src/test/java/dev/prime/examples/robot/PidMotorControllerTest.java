package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import org.junit.jupiter.api.Test;

class PidMotorControllerTest {
  private static final RobotSpec SPEC = RobotSpec.SMALL_INDOOR;

  private static Setpoint setpoint(WheelSpeeds target, WheelSpeeds measured) {
    return new Setpoint(new Estimate(3, Pose.ORIGIN, measured), target);
  }

  @Test
  void atTheTargetSpeedItAppliesTheSteadyStateVoltage() {
    PidMotorController controller = new PidMotorController(SPEC, 0.01);
    WheelSpeeds speeds = new WheelSpeeds(0.2, 0.4);

    DriveCommand command = controller.process(setpoint(speeds, speeds));

    assertEquals(0.2 / SPEC.motorGain(), command.leftVolts(), 1e-9);
    assertEquals(0.4 / SPEC.motorGain(), command.rightVolts(), 1e-9);
    assertFalse(command.arrived());
    assertEquals(speeds, command.target());
  }

  @Test
  void aSlowWheelGetsMoreVoltageThanAFastOne() {
    PidMotorController controller = new PidMotorController(SPEC, 0.01);

    DriveCommand command =
        controller.process(setpoint(new WheelSpeeds(0.3, 0.3), new WheelSpeeds(0.1, 0.5)));

    double steady = 0.3 / SPEC.motorGain();
    assertTrue(command.leftVolts() > steady, "slow left wheel pushed: " + command);
    assertTrue(command.rightVolts() < steady, "fast right wheel held back: " + command);
  }

  @Test
  void neverExceedsTheSupplyVoltage() {
    PidMotorController controller = new PidMotorController(SPEC, 0.01);

    DriveCommand command =
        controller.process(setpoint(new WheelSpeeds(50, -50), WheelSpeeds.STILL));

    assertEquals(SPEC.maxVolts(), command.leftVolts(), 1e-12);
    assertEquals(-SPEC.maxVolts(), command.rightVolts(), 1e-12);
  }
}

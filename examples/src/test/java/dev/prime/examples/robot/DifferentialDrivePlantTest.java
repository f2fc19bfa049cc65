package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.util.ArrayList;
import java.util.List;
import org.junit.jupiter.api.Test;

class DifferentialDrivePlantTest {
  private static final RobotSpec SPEC = RobotSpec.SMALL_INDOOR;

  private static DriveCommand volts(double left, double right) {
    return new DriveCommand(
        new Estimate(0, Pose.ORIGIN, WheelSpeeds.STILL), WheelSpeeds.STILL, left, right, false);
  }

  @Test
  void motorsSettleAtGainTimesVoltage() {
    DifferentialDrivePlant plant = new DifferentialDrivePlant(SPEC, Pose.ORIGIN);
    for (int i = 0; i < 200; i++) { // 2 s = 20 time constants
      plant.step(volts(5, 5), 0.01);
    }

    assertEquals(5 * SPEC.motorGain(), plant.wheelSpeeds().left(), 1e-6);
    assertEquals(0.0, plant.pose().y(), 1e-12);
    assertTrue(plant.pose().x() > 1.5, "drove forward: " + plant.pose());
    assertEquals(plant.pose().x(), plant.leftTravel(), 1e-9);
  }

  @Test
  void voltageIsClampedToTheSupply() {
    DifferentialDrivePlant plant = new DifferentialDrivePlant(SPEC, Pose.ORIGIN);
    for (int i = 0; i < 200; i++) {
      plant.step(volts(1000, 1000), 0.01);
    }

    assertEquals(SPEC.maxVolts() * SPEC.motorGain(), plant.wheelSpeeds().right(), 1e-6);
  }

  @Test
  void encodersPublishWholeTicksOfTheWheels() {
    DifferentialDrivePlant plant = new DifferentialDrivePlant(SPEC, Pose.ORIGIN);
    for (int i = 0; i < 100; i++) {
      plant.step(volts(-5, 5), 0.01);
    }
    WheelEncoders encoders = new WheelEncoders(SPEC);
    List<EncoderReading> published = new ArrayList<>();
    encoders.events().subscribe(published::add);

    EncoderReading reading = encoders.sample(100, plant);

    assertEquals(List.of(reading), published);
    assertEquals(Math.floor(plant.rightTravel() / SPEC.metresPerTick()), reading.rightTicks());
    assertEquals(Math.floor(plant.leftTravel() / SPEC.metresPerTick()), reading.leftTicks());
    assertTrue(reading.leftTicks() < 0 && reading.rightTicks() > 0, "spun on the spot: " + reading);
  }
}

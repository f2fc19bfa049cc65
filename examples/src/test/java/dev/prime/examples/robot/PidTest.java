package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;

import org.junit.jupiter.api.Test;

class PidTest {

  @Test
  void proportionalAloneScalesTheError() {
    Pid pid = new Pid(2, 0, 0, 100);

    assertEquals(3.0, pid.update(1.5, 0.01, 0), 1e-12);
  }

  @Test
  void integralAccumulatesErrorOverTime() {
    Pid pid = new Pid(0, 10, 0, 100);
    pid.update(1, 0.1, 0);

    double output = pid.update(1, 0.1, 0);

    assertEquals(0.2, pid.integral(), 1e-12);
    assertEquals(2.0, output, 1e-12);
  }

  @Test
  void derivativeReactsToTheChangeOfError() {
    Pid pid = new Pid(0, 0, 0.5, 100);
    assertEquals(0.0, pid.update(1, 0.1, 0), 1e-12, "no derivative on the first update");

    assertEquals(5.0, pid.update(2, 0.1, 0), 1e-12);
  }

  @Test
  void biasIsAddedAndOutputIsClamped() {
    Pid pid = new Pid(1, 0, 0, 12);

    assertEquals(7.0, pid.update(2, 0.01, 5), 1e-12);
    assertEquals(12.0, pid.update(100, 0.01, 5), 1e-12);
    assertEquals(-12.0, pid.update(-100, 0.01, 0), 1e-12);
  }

  @Test
  void integralDoesNotWindUpWhileSaturated() {
    Pid pid = new Pid(1, 1, 0, 12);
    for (int i = 0; i < 100; i++) {
      pid.update(50, 0.1, 0);
    }

    assertEquals(0.0, pid.integral(), 1e-12);
  }

  @Test
  void badSettingsAreRejectedWithTheReason() {
    assertEquals(
        "PID output limit must be positive, was 0.0",
        assertThrows(IllegalArgumentException.class, () -> new Pid(1, 0, 0, 0)).getMessage());
    assertEquals(
        "PID dt must be positive seconds, was 0.0",
        assertThrows(IllegalArgumentException.class, () -> new Pid(1, 0, 0, 1).update(1, 0, 0))
            .getMessage());
  }
}

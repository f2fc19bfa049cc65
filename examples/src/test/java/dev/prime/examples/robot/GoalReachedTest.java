package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import org.junit.jupiter.api.Test;

class GoalReachedTest {
  private final GoalReached reached = new GoalReached(new Goal(1, 1), 0.05);

  private static Estimate at(double x, double y) {
    return new Estimate(0, new Pose(x, y, 0), WheelSpeeds.STILL);
  }

  @Test
  void withinTheToleranceIsReached() {
    assertTrue(reached.test(at(1.03, 0.97)));
  }

  @Test
  void outsideTheToleranceIsNot() {
    assertFalse(reached.test(at(1.04, 1.04)));
  }

  @Test
  void toleranceMustBePositive() {
    assertThrows(IllegalArgumentException.class, () -> new GoalReached(new Goal(0, 0), 0));
  }
}

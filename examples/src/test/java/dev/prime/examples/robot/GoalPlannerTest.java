package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertTrue;

import org.junit.jupiter.api.Test;

class GoalPlannerTest {
  private static final RobotSpec SPEC = RobotSpec.SMALL_INDOOR;

  private static Estimate at(Pose pose) {
    return new Estimate(0, pose, WheelSpeeds.STILL);
  }

  @Test
  void farGoalStraightAheadDrivesBothWheelsAtTopSpeed() {
    GoalPlanner planner = new GoalPlanner(new Goal(10, 0), SPEC);
    Estimate estimate = at(Pose.ORIGIN);

    Setpoint setpoint = planner.process(estimate);

    assertSame(estimate, setpoint.estimate());
    assertEquals(GoalPlanner.MAX_SPEED, setpoint.target().left(), 1e-12);
    assertEquals(GoalPlanner.MAX_SPEED, setpoint.target().right(), 1e-12);
  }

  @Test
  void goalOnTheLeftMakesTheRightWheelFaster() {
    GoalPlanner planner = new GoalPlanner(new Goal(1, 1), SPEC);

    WheelSpeeds target = planner.process(at(Pose.ORIGIN)).target();

    assertTrue(target.right() > target.left(), "turns left (counter-clockwise): " + target);
  }

  @Test
  void goalBehindTurnsOnTheSpotWithoutDrivingForward() {
    GoalPlanner planner = new GoalPlanner(new Goal(-1, 0.01), SPEC);

    WheelSpeeds target = planner.process(at(Pose.ORIGIN)).target();

    assertEquals(0.0, target.left() + target.right(), 1e-12, "no forward speed: " + target);
    assertEquals(
        GoalPlanner.MAX_TURN_RATE * SPEC.trackWidth(), target.right() - target.left(), 1e-12);
  }

  @Test
  void slowsDownNearTheGoal() {
    GoalPlanner planner = new GoalPlanner(new Goal(0.1, 0), SPEC);

    WheelSpeeds target = planner.process(at(Pose.ORIGIN)).target();

    assertEquals(GoalPlanner.DISTANCE_GAIN * 0.1, target.left(), 1e-12);
    assertEquals(GoalPlanner.DISTANCE_GAIN * 0.1, target.right(), 1e-12);
  }
}

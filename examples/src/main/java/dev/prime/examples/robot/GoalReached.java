package dev.prime.examples.robot;

import java.util.Objects;
import java.util.function.Predicate;

/**
 * Whether an estimate is within a tolerance of the goal. Used as the guard of the drive chain.
 */
public final class GoalReached implements Predicate<Estimate> {
  private final Goal goal;
  private final double tolerance;

  /**
   * @param goal the goal
   * @param tolerance metres; positive
   */
  public GoalReached(Goal goal, double tolerance) {
    this.goal = Objects.requireNonNull(goal, "goal must not be null");
    if (!(tolerance > 0)) {
      throw new IllegalArgumentException("tolerance must be positive metres, was " + tolerance);
    }
    this.tolerance = tolerance;
  }

  @Override
  public boolean test(Estimate estimate) {
    return estimate.pose().distanceTo(goal) <= tolerance;
  }
}

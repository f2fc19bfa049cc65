package dev.prime.examples.robot;

import java.util.Objects;

/**
 * What one run of the simulation does.
 *
 * @param goal where to drive, starting at the origin facing along x
 * @param maxSteps give up after this many steps
 * @param traceEvery print a trace line every this many steps
 */
public record Mission(Goal goal, int maxSteps, int traceEvery) {

  /** Simulated seconds per step (100 Hz control). */
  public static final double DT = 0.01;

  /**
   * Checks the values.
   *
   * @param goal where to drive, starting at the origin facing along x
   * @param maxSteps give up after this many steps
   * @param traceEvery print a trace line every this many steps
   * @throws IllegalArgumentException if a count is not positive
   */
  public Mission {
    Objects.requireNonNull(goal, "goal must not be null");
    if (maxSteps < 1) {
      throw new IllegalArgumentException("steps must be at least 1, was " + maxSteps);
    }
    if (traceEvery < 1) {
      throw new IllegalArgumentException(
          "trace interval must be at least 1 step, was " + traceEvery);
    }
  }
}

package dev.prime.examples.robot;

/**
 * What the goal planner wants the wheels to do.
 *
 * @param estimate the estimate the plan was made from
 * @param target the wheel speeds to reach
 */
public record Setpoint(Estimate estimate, WheelSpeeds target) {}

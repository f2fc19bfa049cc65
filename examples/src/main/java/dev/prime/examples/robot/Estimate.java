package dev.prime.examples.robot;

/**
 * What odometry believes at one step.
 *
 * @param step the simulation step
 * @param pose the estimated pose
 * @param measured the wheel speeds measured from the encoders over the last step
 */
public record Estimate(long step, Pose pose, WheelSpeeds measured) {}

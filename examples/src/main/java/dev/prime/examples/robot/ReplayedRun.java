package dev.prime.examples.robot;

/**
 * How a replay ended ({@link RobotSimulation#replay}). There is no true pose: a replay has no
 * plant, only the recorded encoder readings.
 *
 * @param reached whether the controller declared the goal reached
 * @param steps control steps run (one per encoder reading fed)
 * @param readings encoder readings in the recording
 * @param estimated the pose odometry believed at the end
 * @param estimatedError distance from the estimated pose to the goal, metres
 */
public record ReplayedRun(
    boolean reached, long steps, long readings, Pose estimated, double estimatedError) {}

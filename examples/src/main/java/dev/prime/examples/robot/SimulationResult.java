package dev.prime.examples.robot;

/**
 * How a run ended.
 *
 * @param reached whether the controller declared the goal reached
 * @param steps steps simulated
 * @param estimated the pose odometry believed at the end
 * @param actual the plant's true pose at the end
 * @param estimatedError distance from the estimated pose to the goal, metres
 * @param actualError distance from the true pose to the goal, metres
 */
public record SimulationResult(
    boolean reached,
    long steps,
    Pose estimated,
    Pose actual,
    double estimatedError,
    double actualError) {}

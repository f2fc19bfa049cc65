package dev.prime.examples.robot;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.PrimeCore;
import dev.prime.Source;
import dev.prime.Token;
import java.util.List;
import java.util.Objects;

/**
 * The topology of the robot: how the blocks are linked. This is the only class of the example
 * that speaks to a {@link PrimeCore}, and it works with any media.
 *
 * <pre>
 *   encoders (event source) ──▶ odometry (service) ──▶ estimates (source)
 *                                                          │ sync collector
 *                                                          ▼
 *            guard(not at goal) { planner ──▶ pid }, otherwise stop ──▶ DriveCommand
 * </pre>
 */
public final class RobotController {

  /** The name of the encoders' source: its recorded values are what a replay feeds back. */
  public static final String ENCODERS = "encoders";

  /** How close to the goal counts as arrived, metres. */
  public static final double TOLERANCE = 0.03;

  /**
   * The services of this topology ({@link PrimeCore#serviceNames()}, the same on every media): on
   * Optimus, the names a process is told to host, or to leave to another process. They are
   * deterministic because every chain is named and the templates' names are made from them.
   */
  public static final List<String> SERVICES =
      List.of("odometry", "planner", "pid", "guard(planner>pid)", "collect(encoders>odometry)");

  private RobotController() {}

  /**
   * Declares the robot's chains and sources on {@code core} and returns the control step: each
   * call waits for odometry's next estimate and returns the command for it.
   *
   * @param core the core (not started yet; the caller starts it)
   * @param encoders the wheel encoders whose readings drive odometry
   * @param spec the robot
   * @param goal where to drive
   * @param dt seconds per simulation step
   * @return the control step
   */
  public static Block<Token, DriveCommand> wire(
      PrimeCore core, WheelEncoders encoders, RobotSpec spec, Goal goal, double dt) {
    Objects.requireNonNull(core, "core must not be null");
    Objects.requireNonNull(encoders, "encoders must not be null");

    // A source linked to a chain: odometry runs as a service on every encoder reading.
    Source<EncoderReading> ticks = core.source(ENCODERS, encoders.events());
    Source<Estimate> estimates =
        ticks.then(core.chain("odometry", new Odometry(spec, dt, Pose.ORIGIN)));

    // chain.then: the planner's setpoints feed the motor controller, fused into one chain.
    Chain<Estimate, DriveCommand> drive =
        core.chain("planner", new GoalPlanner(goal, spec))
            .then(core.chain("pid", new PidMotorController(spec, dt)));

    // Templates: a guard stops the motors at the goal; a sync collector hands the control chain
    // each estimate of the odometry source in turn.
    Chain<Estimate, DriveCommand> guarded =
        core.guard(new GoalReached(goal, TOLERANCE).negate(), drive, DriveCommand::stop);
    return core.syncCollector(estimates).then(guarded).toBlock();
  }
}

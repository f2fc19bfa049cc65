package dev.prime.examples.robot;

import dev.prime.Block;
import dev.prime.PrimeCore;
import dev.prime.Token;
import java.io.PrintStream;
import java.util.Locale;
import java.util.Objects;

/**
 * Runs the robot in simulated time: each step the encoders publish the plant's counts, the
 * control step turns odometry's estimate into motor voltages, and the plant moves for one fixed
 * {@link Mission#DT}. The loop waits for each estimate before it moves the plant, so the output is
 * the same on every run with the same mission.
 */
public final class RobotSimulation {
  private final RobotSpec spec;

  /**
   * @param spec the robot to simulate
   */
  public RobotSimulation(RobotSpec spec) {
    this.spec = Objects.requireNonNull(spec, "spec must not be null");
  }

  /**
   * Declares the robot on {@code core}, starts the core and drives until the goal is reached or
   * the mission's steps run out. The caller owns and closes the core.
   *
   * @param core a new core, not started
   * @param mission the run
   * @param trace receives a line every {@link Mission#traceEvery()} steps
   * @return the outcome
   */
  public SimulationResult run(PrimeCore core, Mission mission, PrintStream trace) {
    Objects.requireNonNull(mission, "mission must not be null");
    Objects.requireNonNull(trace, "trace must not be null");
    WheelEncoders encoders = new WheelEncoders(spec);
    DifferentialDrivePlant plant = new DifferentialDrivePlant(spec, Pose.ORIGIN);
    Block<Token, DriveCommand> control =
        RobotController.wire(core, encoders, spec, mission.goal(), Mission.DT);
    core.start();

    DriveCommand command = null;
    long step = 0;
    for (; step < mission.maxSteps(); step++) {
      encoders.sample(step, plant);
      command = control.process(Token.INSTANCE);
      if (step % mission.traceEvery() == 0 || command.arrived()) {
        trace.println(traceLine(step, command, mission.goal()));
      }
      if (command.arrived()) {
        break;
      }
      plant.step(command, Mission.DT);
    }
    Pose estimated = command == null ? Pose.ORIGIN : command.estimate().pose();
    return new SimulationResult(
        command != null && command.arrived(),
        command != null && command.arrived() ? step + 1 : step,
        estimated,
        plant.pose(),
        estimated.distanceTo(mission.goal()),
        plant.pose().distanceTo(mission.goal()));
  }

  private static String traceLine(long step, DriveCommand command, Goal goal) {
    Pose pose = command.estimate().pose();
    return String.format(
        Locale.ROOT,
        "step %5d  t=%6.2fs  pose %s  to goal %.3f m  volts L %+6.2f R %+6.2f%s",
        step,
        step * Mission.DT,
        pose,
        pose.distanceTo(goal),
        command.leftVolts(),
        command.rightVolts(),
        command.arrived() ? "  arrived" : "");
  }
}

package dev.prime.examples.robot;

import dev.prime.Block;
import dev.prime.PrimeCore;
import dev.prime.Token;
import dev.prime.mcap.McapReader;
import dev.prime.mcap.McapReplay;
import dev.prime.mcap.ReplaySession;
import dev.prime.mcap.TypedMessage;
import java.io.IOException;
import java.io.PrintStream;
import java.nio.file.Path;
import java.util.Locale;
import java.util.Objects;
import java.util.Optional;

/**
 * Runs the robot in simulated time: each step the encoders publish the plant's counts, the
 * control step turns odometry's estimate into motor voltages, and the plant moves for one fixed
 * {@link Mission#DT}. The loop waits for each estimate before it moves the plant, so the output is
 * the same on every run with the same mission.
 *
 * <p>{@link #replay} runs the controller on the encoder readings of a recording instead of the
 * plant's: the control loop is closed through the plant, so feeding the recorded readings back
 * makes odometry, the planner and the motor controller compute again what they computed in the
 * recorded run, and the trace lines (step, estimated pose, distance to goal, volts) are the
 * recorded run's, on any media. The true pose is not part of a replay: there is no plant.
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
      trace(trace, mission, step, command);
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

  /**
   * Declares the robot on {@code core}, starts the core and feeds it the encoder readings
   * recorded in {@code recording} (the {@value RobotController#ENCODERS} channel of a file written
   * with {@code --record}), one per control step, as fast as possible, until the controller
   * declares the goal reached, the readings run out or the mission's steps run out. Trace lines are printed as {@link #run}
   * prints them. The caller owns and closes the core.
   *
   * @param core a new core, not started
   * @param mission the recorded run's mission: its goal, its step limit and its trace interval
   * @param recording an MCAP file with an {@value RobotController#ENCODERS} channel
   * @param trace receives a line every {@link Mission#traceEvery()} steps
   * @return the outcome
   * @throws IOException if the file cannot be read or is not an MCAP file
   * @throws IllegalArgumentException if the file has no encoder channel or its messages are not
   *     encoder readings
   * @throws InterruptedException if interrupted
   */
  public ReplayedRun replay(PrimeCore core, Mission mission, Path recording, PrintStream trace)
      throws IOException, InterruptedException {
    Objects.requireNonNull(mission, "mission must not be null");
    Objects.requireNonNull(recording, "recording must not be null");
    Objects.requireNonNull(trace, "trace must not be null");
    long readings;
    try (McapReader reader = McapReader.open(recording)) {
      readings =
          reader.channel(RobotController.ENCODERS).isPresent()
              ? reader.messageCount(RobotController.ENCODERS)
              : 0;
    }
    WheelEncoders encoders = new WheelEncoders(spec);
    Block<Token, DriveCommand> control =
        RobotController.wire(core, encoders, spec, mission.goal(), Mission.DT);
    core.start();

    DriveCommand command = null;
    long steps = 0;
    try (ReplaySession session =
        McapReplay.of(recording)
            .feed(RobotController.ENCODERS, encoders.events(), EncoderReading.class)
            .open()) {
      Optional<TypedMessage<Object>> fed;
      while (steps < mission.maxSteps() && (fed = session.feedNext()).isPresent()) {
        EncoderReading reading = (EncoderReading) fed.get().value();
        command = control.process(Token.INSTANCE);
        steps++;
        trace(trace, mission, reading.step(), command);
        if (command.arrived()) {
          break;
        }
      }
    }
    Pose estimated = command == null ? Pose.ORIGIN : command.estimate().pose();
    return new ReplayedRun(
        command != null && command.arrived(),
        steps,
        readings,
        estimated,
        estimated.distanceTo(mission.goal()));
  }

  private static void trace(PrintStream trace, Mission mission, long step, DriveCommand command) {
    if (step % mission.traceEvery() == 0 || command.arrived()) {
      trace.println(traceLine(step, command, mission.goal()));
    }
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

package dev.prime.examples.robot;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import java.io.PrintStream;
import java.util.Locale;

/**
 * Runs the differential-drive robot example: {@code robot [--media liberty] [--goal X,Y]}.
 *
 * <p>Exit codes: 0 the goal was reached (or help was printed), 1 it was not reached in the
 * allowed steps, 2 the command line is wrong.
 */
public final class RobotMain {

  private RobotMain() {}

  /**
   * The program.
   *
   * @param args see {@link RobotOptions#USAGE}
   */
  public static void main(String[] args) {
    int code = run(args, System.out, System.err);
    if (code != 0) {
      System.exit(code);
    }
  }

  /**
   * Runs the example and returns its exit code, printing to the given streams.
   *
   * @param args the command line
   * @param out receives the trace and the summary
   * @param err receives usage errors
   * @return the exit code
   */
  public static int run(String[] args, PrintStream out, PrintStream err) {
    RobotOptions options;
    try {
      options = RobotOptions.parse(args);
    } catch (UsageException e) {
      err.println("error: " + e.getMessage());
      err.println(RobotOptions.USAGE);
      return 2;
    }
    if (options.help()) {
      out.println(RobotOptions.USAGE);
      return 0;
    }
    Mission mission = options.mission();
    out.printf(
        Locale.ROOT,
        "robot on media %s: driving from %s to %s, dt %.0f ms, at most %d steps%n",
        options.media().cliName(),
        Pose.ORIGIN,
        mission.goal(),
        Mission.DT * 1000,
        mission.maxSteps());
    SimulationResult result;
    try (PrimeCore core = options.media().create(CoreConfig.builder().name("robot").build())) {
      result = new RobotSimulation(RobotSpec.SMALL_INDOOR).run(core, mission, out);
    }
    out.println(summary(result, mission));
    return result.reached() ? 0 : 1;
  }

  static String summary(SimulationResult result, Mission mission) {
    return String.join(
        System.lineSeparator(),
        String.format(
            Locale.ROOT,
            "%s goal %s after %d steps (%.2f s simulated)",
            result.reached() ? "reached" : "did NOT reach",
            mission.goal(),
            result.steps(),
            result.steps() * Mission.DT),
        "  pose (odometry)   " + result.estimated(),
        "  pose (true)       " + result.actual(),
        String.format(
            Locale.ROOT,
            "  distance error to goal: %.4f m by odometry, %.4f m true (tolerance %.2f m)",
            result.estimatedError(),
            result.actualError(),
            RobotController.TOLERANCE));
  }
}

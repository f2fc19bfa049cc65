package dev.prime.examples.robot;

import dev.prime.PrimeCore;
import dev.prime.PrimeException;
import java.io.PrintStream;
import java.util.Locale;

/**
 * Runs the differential-drive robot example: {@code robot [--media liberty] [--goal X,Y]}. On
 * {@code --media optimus --redis URL --remote planner} the planner runs in another process, a
 * {@link RobotWorker} on the same Redis.
 *
 * <p>Exit codes: 0 the goal was reached (or help was printed), 1 it was not reached in the
 * allowed steps, 2 the command line is wrong, 3 the Redis given by {@code --redis} cannot be
 * reached.
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
    PrimeCore created;
    try {
      created = createCore(options);
    } catch (PrimeException e) {
      err.println("error: " + e.getMessage());
      return 3;
    }
    if (options.redisUrl() != null) {
      out.println(
          "  on Redis "
              + options.redisUrl()
              + " as core '"
              + options.name()
              + "'"
              + (options.remote().isEmpty()
                  ? ""
                  : ", leaving " + options.remote() + " to a robot worker"));
    }
    SimulationResult result;
    try (PrimeCore core = created) {
      result = new RobotSimulation(RobotSpec.SMALL_INDOOR).run(core, mission, out);
    }
    out.println(summary(result, mission));
    return result.reached() ? 0 : 1;
  }

  private static PrimeCore createCore(RobotOptions options) {
    if (options.media() == Media.OPTIMUS) {
      return Media.optimus(options.coreConfig(), options.redisUrl(), options.hosted());
    }
    return options.media().create(options.coreConfig());
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

package dev.prime.examples.robot;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.PrimeException;
import java.io.BufferedReader;
import java.io.IOException;
import java.io.InputStream;
import java.io.InputStreamReader;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.util.List;

/**
 * The other process of the two-process robot: {@code robot-worker --redis URL --hosts
 * SERVICE,... [--goal X,Y] [--name NAME]}. It declares the same topology as {@link RobotMain}
 * (same core name, same goal) and runs only the named services, taking their inputs from Redis
 * and storing their results there, until it is stopped (Ctrl-C, end of input, or a line {@code
 * STOP}). Pair it with {@code robot --media optimus --redis URL --remote SERVICE,...}.
 *
 * <p>Blocks keep their state in the process that hosts them: a worker hosting a stateful block
 * (odometry, pid) serves one mission; the planner holds none and may serve many.
 *
 * <p>Exit codes: 0 stopped, 2 the command line is wrong, 3 the Redis cannot be reached.
 */
public final class RobotWorker {

  /** The usage text. */
  public static final String USAGE =
      String.join(
          System.lineSeparator(),
          "usage: robot-worker --redis URL --hosts SERVICE,... [--goal X,Y] [--name NAME]",
          "  --redis URL       the Redis shared with the robot, like redis://localhost:6379",
          "  --hosts S,...     the services this process runs: "
              + String.join(", ", RobotController.SERVICES),
          "  --goal X,Y        the robot's goal, as given to the robot (default 2,1)",
          "  --name NAME       the core's name, as given to the robot (default robot)",
          "stop it with Ctrl-C, end of input, or a line STOP");

  private RobotWorker() {}

  /**
   * The program.
   *
   * @param args see {@link #USAGE}
   */
  public static void main(String[] args) {
    int code = run(args, System.in, System.out, System.err);
    if (code != 0) {
      System.exit(code);
    }
  }

  /**
   * Runs the worker until {@code in} ends or gives a line {@code STOP}, and returns its exit code.
   *
   * @param args the command line
   * @param in where the stop comes from
   * @param out receives a line {@code READY ...} once the services run
   * @param err receives errors
   * @return the exit code
   */
  public static int run(String[] args, InputStream in, PrintStream out, PrintStream err) {
    Options options;
    try {
      options = Options.parse(args);
    } catch (UsageException e) {
      err.println("error: " + e.getMessage());
      err.println(USAGE);
      return 2;
    }
    PrimeCore core;
    try {
      core =
          Media.optimus(
              CoreConfig.builder().name(options.name).build(), options.redisUrl, options.hosts);
    } catch (PrimeException e) {
      err.println("error: " + e.getMessage());
      return 3;
    }
    Thread closeOnExit = new Thread(core::close, "robot-worker-close");
    Runtime.getRuntime().addShutdownHook(closeOnExit);
    try (core) {
      // Only the hosted services run here, but the whole topology is declared, in the same order.
      RobotController.wire(
          core,
          new WheelEncoders(RobotSpec.SMALL_INDOOR),
          RobotSpec.SMALL_INDOOR,
          options.goal,
          Mission.DT);
      core.start();
      out.println("READY robot worker hosting " + options.hosts + " of core '" + core.name() + "'");
      awaitStop(in);
    } finally {
      try {
        Runtime.getRuntime().removeShutdownHook(closeOnExit);
      } catch (IllegalStateException e) {
        // the JVM is exiting: the hook closes the core
      }
    }
    out.println("STOPPED");
    return 0;
  }

  private static void awaitStop(InputStream in) {
    BufferedReader lines = new BufferedReader(new InputStreamReader(in, StandardCharsets.UTF_8));
    try {
      for (String line = lines.readLine(); line != null; line = lines.readLine()) {
        if (line.strip().equals("STOP")) {
          return;
        }
      }
    } catch (IOException e) {
      // input is gone: stop as at its end
    }
  }

  private record Options(String redisUrl, List<String> hosts, Goal goal, String name) {
    static Options parse(String... args) {
      String redisUrl = null;
      List<String> hosts = null;
      Goal goal = RobotOptions.DEFAULTS.goal();
      String name = RobotOptions.DEFAULTS.name();
      for (int i = 0; i < args.length; i++) {
        String option = args[i];
        String value = null;
        int eq = option.indexOf('=');
        if (option.startsWith("--") && eq > 0) {
          value = option.substring(eq + 1);
          option = option.substring(0, eq);
        }
        if (!List.of("--redis", "--hosts", "--goal", "--name").contains(option)) {
          throw new UsageException("unknown argument '" + args[i] + "'");
        }
        if (value == null) {
          if (i + 1 >= args.length) {
            throw new UsageException(option + " needs a value");
          }
          value = args[++i];
        }
        switch (option) {
          case "--redis" -> redisUrl = RobotOptions.redisUrl(value);
          case "--hosts" -> hosts = RobotOptions.services(option, value);
          case "--goal" -> goal = RobotOptions.goal(value);
          default -> name = RobotOptions.coreName(value);
        }
      }
      if (redisUrl == null) {
        throw new UsageException("--redis URL is required: the Redis shared with the robot");
      }
      if (hosts == null) {
        throw new UsageException("--hosts is required: the services this worker runs");
      }
      return new Options(redisUrl, hosts, goal, name);
    }
  }
}

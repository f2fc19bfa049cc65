package dev.prime.examples.robot;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.PrimeException;
import dev.prime.optimus.EmbeddedRedis;
import java.io.BufferedReader;
import java.io.IOException;
import java.io.InputStream;
import java.io.InputStreamReader;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.util.List;

/**
 * The other process of the two-process robot: {@code robot-worker --hosts SERVICE,... [--redis
 * URL] [--goal X,Y] [--name NAME]}. It declares the same topology as {@link RobotMain} (same core
 * name, same goal) and runs only the named services, taking their inputs from Redis and storing
 * their results there, until it is stopped (Ctrl-C, end of input, or a line {@code STOP}). Pair it
 * with {@code robot --media optimus --redis URL --remote SERVICE,...}. Without {@code --redis} it
 * starts an embedded Redis (listening on 127.0.0.1 only) and prints its URL in its {@code READY}
 * line, so both processes run on one machine with nothing installed.
 *
 * <p>Blocks keep their state in the process that hosts them: a worker hosting a stateful block
 * (odometry, pid) serves one mission; the planner holds none and may serve many.
 *
 * <p>Exit codes: 0 stopped, 2 the command line is wrong, 3 the Redis cannot be reached (or the
 * embedded one cannot start).
 */
public final class RobotWorker {

  /** The usage text. */
  public static final String USAGE =
      String.join(
          System.lineSeparator(),
          "usage: robot-worker --hosts SERVICE,... [--redis URL] [--goal X,Y] [--name NAME]",
          "  --redis URL       the Redis shared with the robot, like redis://localhost:6379"
              + " (default: start an embedded one and print its URL)",
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
    EmbeddedRedis embedded = null;
    PrimeCore core;
    try {
      String redisUrl = options.redisUrl;
      if (redisUrl == null) {
        embedded = EmbeddedRedis.start();
        redisUrl = embedded.getUri();
      }
      core =
          Media.optimus(CoreConfig.builder().name(options.name).build(), redisUrl, options.hosts);
    } catch (PrimeException e) {
      if (embedded != null) {
        embedded.close();
      }
      err.println("error: " + e.getMessage());
      return 3;
    }
    EmbeddedRedis ownRedis = embedded;
    Thread closeOnExit = new Thread(() -> close(core, ownRedis), "robot-worker-close");
    Runtime.getRuntime().addShutdownHook(closeOnExit);
    try {
      // Only the hosted services run here, but the whole topology is declared, in the same order.
      RobotController.wire(
          core,
          new WheelEncoders(RobotSpec.SMALL_INDOOR),
          RobotSpec.SMALL_INDOOR,
          options.goal,
          Mission.DT);
      core.start();
      out.println(
          "READY robot worker hosting "
              + options.hosts
              + " of core '"
              + core.name()
              + "' on "
              + (ownRedis == null ? options.redisUrl : ownRedis.getUri()));
      awaitStop(in);
    } finally {
      close(core, ownRedis);
      try {
        Runtime.getRuntime().removeShutdownHook(closeOnExit);
      } catch (IllegalStateException e) {
        // the JVM is exiting: the hook closes the core as well (closing twice does nothing)
      }
    }
    out.println("STOPPED");
    return 0;
  }

  private static void close(PrimeCore core, EmbeddedRedis redis) {
    try {
      core.close();
    } finally {
      if (redis != null) {
        redis.close();
      }
    }
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
      if (hosts == null) {
        throw new UsageException("--hosts is required: the services this worker runs");
      }
      return new Options(redisUrl, hosts, goal, name);
    }
  }
}

package dev.prime.examples.robot;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.PrimeException;
import dev.prime.RecordingOptions;
import dev.prime.optimus.EmbeddedRedis;
import java.io.BufferedReader;
import java.io.IOException;
import java.io.InputStream;
import java.io.InputStreamReader;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.nio.file.Path;
import java.util.List;
import java.util.Map;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;

/**
 * The other process of the two-process robot: {@code robot-worker --hosts SERVICE,... [--redis
 * URL] [--goal X,Y] [--name NAME] [--record FILE]}. It declares the same topology as {@link
 * RobotMain} (same core name, same goal) and runs only the named services, taking their inputs
 * from Redis and storing their results there, until it is stopped: by a line {@code STOP} on its
 * standard input, or by
 * SIGTERM / Ctrl-C (a shutdown hook closes the core and prints {@code STOPPED}). The end of its
 * standard input does not stop it, so it runs under systemd or Docker with stdin on {@code
 * /dev/null}. With {@code --record FILE} it records what it hosts and writes it to the MCAP file
 * when it stops, for {@code dev.prime.mcap.McapMerge} to join with the robot's file. Pair it
 * with {@code robot --media optimus --redis URL --remote SERVICE,...}. Without {@code --redis} it
 * starts an embedded Redis (listening on 127.0.0.1 only) and prints its URL in its {@code READY}
 * line, so both processes run on one machine with nothing installed.
 *
 * <p>Blocks keep their state in the process that hosts them: a worker hosting a stateful block
 * (odometry, pid) serves one mission; the planner holds none and may serve many.
 *
 * <p>Exit codes: 0 stopped by a line {@code STOP}, 2 the command line is wrong, 3 the Redis cannot
 * be reached (or the embedded one cannot start), 4 the recording cannot be written; stopped by a
 * signal the JVM exits with 128 + the signal's number (143 for SIGTERM, 130 for Ctrl-C's SIGINT)
 * after the core is closed.
 */
public final class RobotWorker {

  /** The usage text. */
  public static final String USAGE =
      String.join(
          System.lineSeparator(),
          "usage: robot-worker --hosts SERVICE,... [--redis URL] [--goal X,Y] [--name NAME]"
              + " [--record FILE]",
          "  --redis URL       the Redis shared with the robot, like redis://localhost:6379"
              + " (default: start an embedded one and print its URL)",
          "  --hosts S,...     the services this process runs: "
              + String.join(", ", RobotController.SERVICES),
          "  --goal X,Y        the robot's goal, as given to the robot (default 2,1)",
          "  --name NAME       the core's name, as given to the robot (default robot)",
          "  --record FILE     record what this worker hosts and write it to the MCAP file FILE"
              + " when it stops (merge it with the robot's: dev.prime.mcap.McapMerge)",
          "stop it with a line STOP, SIGTERM or Ctrl-C (the end of input does not stop it)");

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
   * Values kept per recorded service with {@code --record}: 100,000, over 16 minutes at 100 Hz
   * (the ring fills as values come; older values fall out, counted in the file).
   */
  static final int RECORDED_PER_SERVICE = 100_000;

  /** How long a signal's shutdown hook waits for the worker to close before the JVM exits. */
  private static final long CLOSE_ON_SIGNAL_SECONDS = 30;

  /**
   * Runs the worker until {@code in} gives a line {@code STOP} or the JVM shuts down (SIGTERM,
   * Ctrl-C), and returns its exit code. The end of {@code in} does not stop it.
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
      CoreConfig.Builder config = CoreConfig.builder().name(options.name);
      if (options.record != null) {
        config.recording(RecordingOptions.ring(RECORDED_PER_SERVICE));
      }
      core = Media.optimus(config.build(), redisUrl, options.hosts);
    } catch (PrimeException e) {
      if (embedded != null) {
        embedded.close();
      }
      err.println("error: " + e.getMessage());
      return 3;
    }
    EmbeddedRedis ownRedis = embedded;
    CountDownLatch stopRequested = new CountDownLatch(1);
    boolean recordFailed = false;
    CountDownLatch stopped = new CountDownLatch(1);
    Thread closeOnExit =
        new Thread(
            () -> {
              // a signal: let run() close the core and say STOPPED, as a STOP line would
              stopRequested.countDown();
              try {
                if (!stopped.await(CLOSE_ON_SIGNAL_SECONDS, TimeUnit.SECONDS)) {
                  close(core, ownRedis, err);
                }
              } catch (InterruptedException e) {
                close(core, ownRedis, err);
              }
            },
            "robot-worker-close");
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
      awaitStop(in, stopRequested);
      if (options.record != null
          && !RobotMain.record(
              core.recording(),
              options.record,
              Map.of(
                  RunArguments.WORKER_METADATA,
                  RunArguments.ofWorker(options.goal, options.name, options.hosts)),
              out,
              err)) {
        recordFailed = true;
      }
    } finally {
      try {
        close(core, ownRedis, err);
        try {
          Runtime.getRuntime().removeShutdownHook(closeOnExit);
        } catch (IllegalStateException e) {
          // the JVM is exiting (a signal): its hook is waiting for this close
        }
        out.println("STOPPED");
        out.flush();
      } finally {
        stopped.countDown(); // only now may a signal's hook return and the JVM halt
      }
    }
    return recordFailed ? 4 : 0;
  }

  private static void close(PrimeCore core, EmbeddedRedis redis, PrintStream err) {
    try {
      core.close();
    } catch (RuntimeException e) {
      // on a signal the embedded Redis's own hook may stop it at the same time: still stop
      err.println("error: closing the core: " + e);
    } finally {
      if (redis != null) {
        redis.close();
      }
    }
  }

  /**
   * Returns once {@code in} gives a line {@code STOP} or a stop is requested (by the shutdown
   * hook). The input is read on a daemon thread, so a blocked read never holds the JVM; its end
   * (or failure) leaves the worker running.
   */
  private static void awaitStop(InputStream in, CountDownLatch stopRequested) {
    Thread reader =
        new Thread(
            () -> {
              BufferedReader lines =
                  new BufferedReader(new InputStreamReader(in, StandardCharsets.UTF_8));
              try {
                for (String line = lines.readLine(); line != null; line = lines.readLine()) {
                  if (line.strip().equals("STOP")) {
                    stopRequested.countDown();
                    return;
                  }
                }
              } catch (IOException e) {
                // input is gone: as at its end, keep running until a signal
              }
            },
            "robot-worker-stdin");
    reader.setDaemon(true);
    reader.start();
    try {
      stopRequested.await();
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
    }
  }

  private record Options(
      String redisUrl, List<String> hosts, Goal goal, String name, Path record) {
    static Options parse(String... args) {
      String redisUrl = null;
      List<String> hosts = null;
      Goal goal = RobotOptions.DEFAULTS.goal();
      String name = RobotOptions.DEFAULTS.name();
      Path record = null;
      for (int i = 0; i < args.length; i++) {
        String option = args[i];
        String value = null;
        int eq = option.indexOf('=');
        if (option.startsWith("--") && eq > 0) {
          value = option.substring(eq + 1);
          option = option.substring(0, eq);
        }
        if (!List.of("--redis", "--hosts", "--goal", "--name", "--record").contains(option)) {
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
          case "--record" -> record = RobotOptions.recordFile(value);
          default -> name = RobotOptions.coreName(value);
        }
      }
      if (hosts == null) {
        throw new UsageException("--hosts is required: the services this worker runs");
      }
      return new Options(redisUrl, hosts, goal, name, record);
    }
  }
}

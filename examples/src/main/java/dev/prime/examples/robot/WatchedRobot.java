package dev.prime.examples.robot;

import dev.prime.Block;
import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.RecordingOptions;
import dev.prime.Token;
import dev.prime.inspector.PrimeInspector;
import java.io.PrintStream;
import java.io.UncheckedIOException;
import java.net.InetAddress;
import java.net.InetSocketAddress;
import java.net.URI;
import java.util.Locale;
import java.util.Objects;
import java.util.concurrent.TimeUnit;

/**
 * The robot example on a live diagram page ({@link PrimeInspector}): the robot drives to its goal
 * in real time (one control step every {@link Mission#DT} of wall-clock time) and then holds
 * there, its sensors still reporting, while a browser shows the diagram with each node's rate,
 * processing time and failures, and plots the values of a chosen source or chain. The core runs
 * with metrics and recording on.
 *
 * <pre>
 * ./mvnw -q -pl examples -am test-compile exec:java \
 *     -Dexec.mainClass=dev.prime.examples.robot.WatchedRobot -Dexec.args="--port 8080"
 * </pre>
 *
 * <p>Exit codes: 0 the run ended (the goal reached or not), 2 the command line is wrong, 3 the
 * port cannot be opened.
 */
public final class WatchedRobot implements AutoCloseable {
  /** The usage text. */
  public static final String USAGE =
      String.join(
          System.lineSeparator(),
          "usage: watched-robot [--media NAME] [--goal X,Y] [--port N] [--seconds S] [--help]",
          "  --media NAME   the media to run on: " + Media.knownNames() + " (default liberty)",
          "  --goal X,Y     where to drive, in metres from the start (default 2,1)",
          "  --port N       the page's port on 127.0.0.1 (default 8080; 0 picks a free one)",
          "  --seconds S    how long to run before closing (default 120)",
          "with Maven: ./mvnw -q -pl examples -am test-compile exec:java"
              + " -Dexec.mainClass=dev.prime.examples.robot.WatchedRobot -Dexec.args=\"--port 8080\"");

  private static final RobotSpec SPEC = RobotSpec.SMALL_INDOOR;

  private final PrimeCore core;
  private final PrimeInspector inspector;
  private final Thread driver;
  private volatile boolean driving = true;
  private volatile long steps;
  private volatile DriveCommand last;

  /**
   * Declares the robot on a new core of {@code media} (metrics and recording on), serves its page
   * on {@code address}, starts the core and starts driving.
   *
   * @param media the media to run on
   * @param goal where to drive
   * @param address where the page listens
   * @throws UncheckedIOException if the address cannot be bound
   */
  public WatchedRobot(Media media, Goal goal, InetSocketAddress address) {
    Objects.requireNonNull(goal, "goal must not be null");
    core =
        media.create(
            CoreConfig.builder()
                .name("robot")
                .metrics(true)
                .recording(RecordingOptions.defaults())
                .build());
    WheelEncoders encoders = new WheelEncoders(SPEC);
    DifferentialDrivePlant plant = new DifferentialDrivePlant(SPEC, Pose.ORIGIN);
    Block<Token, DriveCommand> control;
    PrimeInspector page = null;
    try {
      control = RobotController.wire(core, encoders, SPEC, goal, Mission.DT);
      page = PrimeInspector.start(core, address);
      core.start();
    } catch (RuntimeException e) {
      if (page != null) {
        page.close(); // its threads and port, then the core's
      }
      core.close();
      throw e;
    }
    inspector = page;
    driver = new Thread(() -> drive(encoders, plant, control), "robot-driver");
    driver.start();
  }

  /** One control step every {@link Mission#DT} of wall-clock time until {@link #close()}. */
  private void drive(WheelEncoders encoders, DifferentialDrivePlant plant, Block<Token, DriveCommand> control) {
    long periodNanos = (long) (Mission.DT * 1e9);
    long start = System.nanoTime();
    for (long step = 0; driving; step++) {
      encoders.sample(step, plant);
      DriveCommand command = control.process(Token.INSTANCE);
      if (!command.arrived()) {
        plant.step(command, Mission.DT);
      }
      last = command;
      steps = step + 1;
      long wait = start + (step + 1) * periodNanos - System.nanoTime();
      if (wait > 0) {
        try {
          TimeUnit.NANOSECONDS.sleep(wait); // real-time pacing of the simulation
        } catch (InterruptedException e) {
          return;
        }
      }
    }
  }

  /** {@return the page's address} */
  public URI uri() {
    return inspector.uri();
  }

  /** {@return the core the robot runs on} */
  public PrimeCore core() {
    return core;
  }

  /** {@return the control steps done so far} */
  public long steps() {
    return steps;
  }

  /** {@return whether the robot has reached its goal} */
  public boolean arrived() {
    DriveCommand command = last;
    return command != null && command.arrived();
  }

  /** {@return where odometry puts the robot now} */
  public Pose pose() {
    DriveCommand command = last;
    return command == null ? Pose.ORIGIN : command.estimate().pose();
  }

  /** Stops driving, then closes the page and the core. */
  @Override
  public void close() {
    driving = false;
    try {
      driver.join(5_000);
      if (driver.isAlive()) {
        driver.interrupt();
        driver.join(5_000);
      }
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
    } finally {
      inspector.close();
      core.close();
    }
  }

  /**
   * The program.
   *
   * @param args see {@link #USAGE}
   * @throws InterruptedException if interrupted while the robot runs
   */
  public static void main(String[] args) throws InterruptedException {
    int code = run(args, System.out, System.err);
    if (code != 0) {
      System.exit(code);
    }
  }

  /**
   * Runs the watched robot for the given time and returns the exit code.
   *
   * @param args the command line (see {@link #USAGE})
   * @param out receives the page's address and the summary
   * @param err receives usage errors
   * @return the exit code
   * @throws InterruptedException if interrupted while the robot runs
   */
  public static int run(String[] args, PrintStream out, PrintStream err) throws InterruptedException {
    Media media = Media.LIBERTY;
    Goal goal = RobotOptions.DEFAULTS.goal();
    int port = 8080;
    long seconds = 120;
    try {
      for (int i = 0; i < args.length; i++) {
        String option = args[i];
        if (option.equals("--help") || option.equals("-h")) {
          out.println(USAGE);
          return 0;
        }
        if (!option.equals("--media") && !option.equals("--goal") && !option.equals("--port")
            && !option.equals("--seconds")) {
          throw new UsageException("unknown argument '" + option + "'");
        }
        if (i + 1 >= args.length) {
          throw new UsageException(option + " needs a value");
        }
        String value = args[++i];
        switch (option) {
          case "--media" -> media = mediaNamed(value);
          case "--goal" -> goal = RobotOptions.goal(value);
          case "--port" -> port = number(option, value, 0, 65_535);
          default -> seconds = number(option, value, 1, 86_400);
        }
      }
    } catch (UsageException e) {
      err.println("error: " + e.getMessage());
      err.println(USAGE);
      return 2;
    }
    WatchedRobot robot;
    try {
      robot = new WatchedRobot(media, goal, new InetSocketAddress(InetAddress.getLoopbackAddress(), port));
    } catch (UncheckedIOException e) {
      err.println("error: " + e.getMessage());
      return 3;
    }
    try (robot) {
      out.println("robot on media " + media.cliName() + " driving to " + goal + " in real time");
      out.println("watch it at " + robot.uri() + " (for " + seconds + " s)");
      TimeUnit.SECONDS.sleep(seconds);
      out.printf(
          Locale.ROOT,
          "%s after %d steps; odometry says %s%n",
          robot.arrived() ? "at the goal" : "not at the goal",
          robot.steps(),
          robot.pose());
    }
    return 0;
  }

  private static Media mediaNamed(String value) {
    try {
      return Media.byName(value);
    } catch (IllegalArgumentException e) {
      throw new UsageException(e.getMessage());
    }
  }

  private static int number(String option, String value, int min, int max) {
    try {
      int n = Integer.parseInt(value.trim());
      if (n >= min && n <= max) {
        return n;
      }
    } catch (NumberFormatException e) {
      // reported below
    }
    throw new UsageException(
        option + " wants a whole number from " + min + " to " + max + "; got '" + value + "'");
  }
}

package dev.prime.examples.robot;

/**
 * The robot example's command line.
 *
 * @param media the media to run on
 * @param goal where to drive
 * @param maxSteps give up after this many steps
 * @param traceEvery print a trace line every this many steps
 * @param help whether only the usage was asked for
 */
public record RobotOptions(Media media, Goal goal, int maxSteps, int traceEvery, boolean help) {

  /** The usage text. */
  public static final String USAGE =
      String.join(
          System.lineSeparator(),
          "usage: robot [--media NAME] [--goal X,Y] [--steps N] [--trace-every N] [--help]",
          "  --media NAME      the media to run on: " + Media.knownNames() + " (default liberty)",
          "  --goal X,Y        where to drive, in metres from the start (default 2,1)",
          "  --steps N         give up after N steps of 10 ms simulated time (default 3000)",
          "  --trace-every N   print a trace line every N steps (default 100)",
          "with Maven: ./mvnw -q -pl examples -am test-compile exec:java"
              + " -Dexec.args=\"--goal 1.5,-0.5\"");

  /** The defaults: Liberty, goal (2, 1), at most 3000 steps, a trace line every 100. */
  public static final RobotOptions DEFAULTS =
      new RobotOptions(Media.LIBERTY, new Goal(2, 1), 3000, 100, false);

  /** The mission these options describe. */
  public Mission mission() {
    return new Mission(goal, maxSteps, traceEvery);
  }

  /**
   * Parses a command line; options may be given as {@code --name value} or {@code --name=value}.
   *
   * @param args the arguments
   * @return the options
   * @throws UsageException if an argument is unknown, lacks its value or has a bad value
   */
  public static RobotOptions parse(String... args) {
    Media media = DEFAULTS.media;
    Goal goal = DEFAULTS.goal;
    int maxSteps = DEFAULTS.maxSteps;
    int traceEvery = DEFAULTS.traceEvery;
    for (int i = 0; i < args.length; i++) {
      String arg = args[i];
      if (arg.equals("--help") || arg.equals("-h")) {
        return new RobotOptions(media, goal, maxSteps, traceEvery, true);
      }
      String name = arg;
      String value = null;
      int eq = arg.indexOf('=');
      if (arg.startsWith("--") && eq > 0) {
        name = arg.substring(0, eq);
        value = arg.substring(eq + 1);
      }
      switch (name) {
        case "--media", "--goal", "--steps", "--trace-every" -> {
          if (value == null) {
            if (i + 1 >= args.length) {
              throw new UsageException(name + " needs a value");
            }
            value = args[++i];
          }
        }
        default -> throw new UsageException("unknown argument '" + arg + "'");
      }
      switch (name) {
        case "--media" -> media = media(value);
        case "--goal" -> goal = goal(value);
        case "--steps" -> maxSteps = positive(name, value);
        default -> traceEvery = positive(name, value);
      }
    }
    return new RobotOptions(media, goal, maxSteps, traceEvery, false);
  }

  private static Media media(String value) {
    try {
      return Media.byName(value);
    } catch (IllegalArgumentException e) {
      throw new UsageException(e.getMessage());
    }
  }

  private static Goal goal(String value) {
    String[] parts = value.split(",", -1);
    if (parts.length != 2) {
      throw new UsageException(
          "--goal wants two numbers X,Y in metres, like 2,1; got '" + value + "'");
    }
    try {
      return new Goal(Double.parseDouble(parts[0].trim()), Double.parseDouble(parts[1].trim()));
    } catch (IllegalArgumentException e) {
      throw new UsageException(
          "--goal wants two finite numbers X,Y in metres, like 2,1; got '" + value + "'");
    }
  }

  private static int positive(String name, String value) {
    try {
      int n = Integer.parseInt(value.trim());
      if (n >= 1) {
        return n;
      }
    } catch (NumberFormatException e) {
      // reported below
    }
    throw new UsageException(name + " wants a whole number of at least 1; got '" + value + "'");
  }
}

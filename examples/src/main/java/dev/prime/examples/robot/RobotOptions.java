package dev.prime.examples.robot;

import dev.prime.CoreConfig;
import dev.prime.RecordingOptions;
import dev.prime.optimus.OptimusCore;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.LinkedHashSet;
import java.util.List;
import java.util.Set;

/**
 * The robot example's command line.
 *
 * @param media the media to run on
 * @param goal where to drive
 * @param maxSteps give up after this many steps
 * @param traceEvery print a trace line every this many steps
 * @param help whether only the usage was asked for
 * @param redisUrl the Redis the Optimus media uses, or {@code null} for an embedded one
 * @param remote the services another process runs (see {@link RobotWorker}); empty: none
 * @param name the core's name; processes that share a topology on one Redis use the same one
 * @param record write the run's recording to this MCAP file at the end, or {@code null}
 * @param replay feed the encoder readings recorded in this MCAP file instead of the simulated
 *     plant's, or {@code null}
 * @param given the options given on the command line ({@code --goal}, ...); the others have
 *     their defaults, which a replay takes from the recording instead (see {@link RunArguments})
 */
public record RobotOptions(
    Media media,
    Goal goal,
    int maxSteps,
    int traceEvery,
    boolean help,
    String redisUrl,
    List<String> remote,
    String name,
    Path record,
    Path replay,
    Set<String> given) {

  /** The usage text. */
  public static final String USAGE =
      String.join(
          System.lineSeparator(),
          "usage: robot [--media NAME] [--goal X,Y] [--steps N] [--trace-every N]"
              + " [--redis URL [--remote SERVICE,...]] [--name NAME]"
              + " [--record FILE | --replay FILE] [--help]",
          "  --media NAME      the media to run on: " + Media.knownNames() + " (default liberty)",
          "  --goal X,Y        where to drive, in metres from the start (default 2,1)",
          "  --steps N         give up after N steps of 10 ms simulated time (default 3000)",
          "  --trace-every N   print a trace line every N steps (default 100)",
          "  --redis URL       optimus only: use the Redis at URL, like redis://localhost:6379"
              + " (default: an embedded Redis of its own)",
          "  --remote S,...    optimus with --redis only: leave these services to a robot worker"
              + " process; services: " + String.join(", ", RobotController.SERVICES),
          "  --name NAME       the core's name, shared with the worker (default robot)",
          "  --record FILE     record every source and chain and write them to the MCAP file FILE"
              + " at the end (one channel per recorded service, and the run's arguments); with"
              + " --remote, what this process hosts: merge it with the worker's file"
              + " (dev.prime.mcap.McapMerge)",
          "  --replay FILE     drive the controller with the encoder readings recorded in FILE"
              + " instead of the simulated robot (the recorded run's --goal, --steps and"
              + " --trace-every unless given)",
          "with Maven: ./mvnw -q -pl examples -am test-compile exec:java"
              + " -Dexec.args=\"--goal 1.5,-0.5\"");

  /** The defaults: Liberty, goal (2, 1), at most 3000 steps, a trace line every 100. */
  public static final RobotOptions DEFAULTS =
      new RobotOptions(
          Media.LIBERTY,
          new Goal(2, 1),
          3000,
          100,
          false,
          null,
          List.of(),
          "robot",
          null,
          null,
          Set.of());

  /**
   * Copies {@code remote}.
   *
   * @param media the media to run on
   * @param goal where to drive
   * @param maxSteps give up after this many steps
   * @param traceEvery print a trace line every this many steps
   * @param help whether only the usage was asked for
   * @param redisUrl the Redis the Optimus media uses, or {@code null} for an embedded one
   * @param remote the services another process runs (see {@link RobotWorker}); empty: none
   * @param name the core's name; processes that share a topology on one Redis use the same one
   * @param record write the run's recording to this MCAP file at the end, or {@code null}
   * @param replay feed the encoder readings recorded in this MCAP file, or {@code null}
   * @param given the options given on the command line
   */
  public RobotOptions {
    remote = List.copyOf(remote);
    given = Set.copyOf(given);
  }

  /**
   * These options with a mission's goal, step limit and trace interval (a replay's, from the
   * recording).
   *
   * @param mission the mission
   * @return new options
   */
  public RobotOptions withMission(Mission mission) {
    return new RobotOptions(
        media,
        mission.goal(),
        mission.maxSteps(),
        mission.traceEvery(),
        help,
        redisUrl,
        remote,
        name,
        record,
        replay,
        given);
  }

  /** {@return the mission these options describe} */
  public Mission mission() {
    return new Mission(goal, maxSteps, traceEvery);
  }

  /**
   * {@return the core's settings: its name and, with {@link #record}, a recording whose ring
   * holds every value of the run (one per step and recorded service)}
   */
  public CoreConfig coreConfig() {
    CoreConfig.Builder builder = CoreConfig.builder().name(name);
    if (record != null) {
      builder.recording(RecordingOptions.ring(maxSteps + 1));
    }
    return builder.build();
  }

  /**
   * {@return the services this process hosts: {@code null} (all of them) unless some are {@link
   * #remote}}
   */
  public List<String> hosted() {
    if (remote.isEmpty()) {
      return null;
    }
    List<String> hosted = new ArrayList<>(RobotController.SERVICES);
    hosted.removeAll(remote);
    return hosted;
  }

  /**
   * Parses a command line; options may be given as {@code --name value} or {@code --name=value}.
   *
   * @param args the arguments
   * @return the options
   * @throws UsageException if an argument is unknown, lacks its value, has a bad value, or does
   *     not apply to the chosen media
   */
  public static RobotOptions parse(String... args) {
    Media media = DEFAULTS.media;
    Goal goal = DEFAULTS.goal;
    int maxSteps = DEFAULTS.maxSteps;
    int traceEvery = DEFAULTS.traceEvery;
    String redisUrl = null;
    List<String> remote = List.of();
    String name = DEFAULTS.name;
    Path record = null;
    Path replay = null;
    Set<String> given = new LinkedHashSet<>();
    for (int i = 0; i < args.length; i++) {
      String arg = args[i];
      if (arg.equals("--help") || arg.equals("-h")) {
        return DEFAULTS.withHelp();
      }
      String option = arg;
      String value = null;
      int eq = arg.indexOf('=');
      if (arg.startsWith("--") && eq > 0) {
        option = arg.substring(0, eq);
        value = arg.substring(eq + 1);
      }
      switch (option) {
        case "--media", "--goal", "--steps", "--trace-every", "--redis", "--remote", "--name",
            "--record", "--replay" -> {
          if (value == null) {
            if (i + 1 >= args.length) {
              throw new UsageException(option + " needs a value");
            }
            value = args[++i];
          }
        }
        default -> throw new UsageException("unknown argument '" + arg + "'");
      }
      given.add(option);
      switch (option) {
        case "--media" -> media = media(value);
        case "--goal" -> goal = goal(value);
        case "--steps" -> maxSteps = positive(option, value);
        case "--redis" -> redisUrl = redisUrl(value);
        case "--remote" -> remote = services(option, value);
        case "--name" -> name = coreName(value);
        case "--record" -> record = recordFile(value);
        case "--replay" -> replay = replayFile(value);
        default -> traceEvery = positive(option, value);
      }
    }
    if (redisUrl != null && media != Media.OPTIMUS) {
      throw new UsageException("--redis only applies to --media optimus");
    }
    if (!remote.isEmpty() && redisUrl == null) {
      throw new UsageException(
          "--remote needs --redis URL (and --media optimus): the worker that runs those services"
              + " must reach the same Redis");
    }
    if (record != null && replay != null) {
      throw new UsageException(
          "--record and --replay cannot be combined: record a run first, then replay its file");
    }
    return new RobotOptions(
        media, goal, maxSteps, traceEvery, false, redisUrl, remote, name, record, replay, given);
  }

  private RobotOptions withHelp() {
    return new RobotOptions(
        media, goal, maxSteps, traceEvery, true, redisUrl, remote, name, record, replay, given);
  }

  static Path recordFile(String value) {
    Path file = Path.of(value);
    Path parent = file.toAbsolutePath().getParent();
    if (value.isBlank() || Files.isDirectory(file) || parent == null || !Files.isDirectory(parent)) {
      throw new UsageException(
          "--record wants a file in an existing directory, like run.mcap; got '" + value + "'");
    }
    return file;
  }

  static Path replayFile(String value) {
    Path file = Path.of(value);
    if (!Files.isRegularFile(file)) {
      throw new UsageException(
          "--replay: no file '" + value + "'; give an MCAP file written with --record");
    }
    return file;
  }

  private static Media media(String value) {
    try {
      return Media.byName(value);
    } catch (IllegalArgumentException e) {
      throw new UsageException(e.getMessage());
    }
  }

  static Goal goal(String value) {
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

  static String redisUrl(String value) {
    try {
      OptimusCore.builder().redis(value);
      return value;
    } catch (IllegalArgumentException e) {
      throw new UsageException("--redis: " + e.getMessage());
    }
  }

  static List<String> services(String option, String value) {
    Set<String> names = new LinkedHashSet<>();
    for (String part : value.split(",", -1)) {
      String service = part.trim();
      if (!RobotController.SERVICES.contains(service)) {
        throw new UsageException(
            option + ": unknown service '" + service + "'; the robot's services: "
                + String.join(", ", RobotController.SERVICES));
      }
      names.add(service);
    }
    return List.copyOf(names);
  }

  static String coreName(String value) {
    try {
      return CoreConfig.builder().name(value).build().name();
    } catch (IllegalArgumentException e) {
      throw new UsageException("--name: " + e.getMessage());
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

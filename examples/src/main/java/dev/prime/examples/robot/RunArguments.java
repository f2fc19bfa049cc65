package dev.prime.examples.robot;

import dev.prime.mcap.McapReader;
import java.io.IOException;
import java.nio.file.Path;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Locale;
import java.util.Map;

/**
 * The run's arguments stored in its recording, so that {@code --replay FILE} reproduces the run
 * without being told its goal: {@code --record} writes a Metadata record {@value #METADATA} (the
 * goal, the step limit, the trace interval, the media, the core's name and the services left to a
 * worker) into the MCAP file, and a replay takes from it every one of these that its own command
 * line does not give. A worker's file has a {@value #WORKER_METADATA} record instead (its goal,
 * name and hosted services); a merged file has both.
 */
public final class RunArguments {
  /** The Metadata record of the robot's run. */
  public static final String METADATA = "robot.run";

  /** The Metadata record of a worker's run. */
  public static final String WORKER_METADATA = "robot.worker";

  private RunArguments() {}

  /**
   * {@return the {@value #METADATA} record of a run}
   *
   * @param options the run's options
   */
  public static Map<String, String> of(RobotOptions options) {
    Map<String, String> pairs = new LinkedHashMap<>();
    pairs.put("goal", goal(options.goal()));
    pairs.put("steps", Integer.toString(options.maxSteps()));
    pairs.put("trace_every", Integer.toString(options.traceEvery()));
    pairs.put("media", options.media().cliName());
    pairs.put("name", options.name());
    pairs.put("remote", String.join(",", options.remote()));
    return pairs;
  }

  /**
   * {@return the {@value #WORKER_METADATA} record of a worker's run}
   *
   * @param goal the goal the worker was given
   * @param name the core's name
   * @param hosts the services it hosts
   */
  public static Map<String, String> ofWorker(Goal goal, String name, List<String> hosts) {
    Map<String, String> pairs = new LinkedHashMap<>();
    pairs.put("goal", goal(goal));
    pairs.put("name", name);
    pairs.put("hosts", String.join(",", hosts));
    return pairs;
  }

  /** The goal as {@code --goal} takes it, exactly (Java's shortest round-tripping doubles). */
  private static String goal(Goal goal) {
    return goal.x() + "," + goal.y();
  }

  /**
   * The options of a replay: the recorded run's goal, step limit and trace interval where the
   * command line does not give them.
   *
   * @param options the replay's options ({@link RobotOptions#replay()} set)
   * @return the options to replay with, and what was taken from the file
   * @throws IOException if the file cannot be read
   * @throws IllegalArgumentException if the file's {@value #METADATA} record is malformed
   */
  public static Replay forReplay(RobotOptions options) throws IOException {
    List<Map<String, String>> records;
    try (McapReader reader = McapReader.open(options.replay())) {
      records = reader.metadata(METADATA);
    }
    if (records.isEmpty()) {
      return new Replay(options, Map.of());
    }
    Map<String, String> recorded = records.get(0);
    Map<String, String> taken = new LinkedHashMap<>();
    Goal goal = options.goal();
    int steps = options.maxSteps();
    int traceEvery = options.traceEvery();
    try {
      if (!options.given().contains("--goal") && recorded.containsKey("goal")) {
        goal = RobotOptions.goal(recorded.get("goal"));
        taken.put("--goal", recorded.get("goal"));
      }
      if (!options.given().contains("--steps") && recorded.containsKey("steps")) {
        steps = Integer.parseInt(recorded.get("steps"));
        taken.put("--steps", recorded.get("steps"));
      }
      if (!options.given().contains("--trace-every") && recorded.containsKey("trace_every")) {
        traceEvery = Integer.parseInt(recorded.get("trace_every"));
        taken.put("--trace-every", recorded.get("trace_every"));
      }
      return new Replay(options.withMission(new Mission(goal, steps, traceEvery)), taken);
    } catch (IllegalArgumentException e) { // UsageException too
      throw new IllegalArgumentException(
          "the " + METADATA + " record of " + options.replay() + " is malformed (" + recorded
              + "): " + e.getMessage() + "; give --goal, --steps and --trace-every yourself",
          e);
    }
  }

  /**
   * A replay's options and what they took from the recording.
   *
   * @param options the options to replay with
   * @param taken the options taken from the file, as {@code --goal} → {@code 1.0,0.5}; empty if
   *     the file stores no run (recorded before the arguments were stored, or not by the robot)
   */
  public record Replay(RobotOptions options, Map<String, String> taken) {
    /**
     * Copies the map.
     *
     * @param options the options to replay with
     * @param taken the options taken from the file
     */
    public Replay {
      taken = Map.copyOf(taken);
    }

    /** {@return a line saying what was taken from the file, or an empty string} */
    public String describe() {
      if (taken.isEmpty()) {
        return "";
      }
      StringBuilder line = new StringBuilder("  from the recording:");
      for (String option : List.of("--goal", "--steps", "--trace-every")) {
        if (taken.containsKey(option)) {
          line.append(String.format(Locale.ROOT, " %s %s", option, taken.get(option)));
        }
      }
      return line.toString();
    }
  }
}

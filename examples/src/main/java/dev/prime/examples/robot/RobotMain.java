package dev.prime.examples.robot;

import dev.prime.PrimeCore;
import dev.prime.PrimeException;
import dev.prime.Recording;
import dev.prime.mcap.McapFormatException;
import dev.prime.mcap.McapRecorder;
import dev.prime.mcap.McapWriterOptions;
import dev.prime.mcap.RecordingMcap;
import java.io.IOException;
import java.io.PrintStream;
import java.io.UncheckedIOException;
import java.nio.file.Path;
import java.util.LinkedHashMap;
import java.util.Locale;
import java.util.Map;
import java.util.stream.Collectors;

/**
 * Runs the differential-drive robot example: {@code robot [--media liberty] [--goal X,Y]}. On
 * {@code --media optimus --redis URL --remote planner} the planner runs in another process, a
 * {@link RobotWorker} on the same Redis. {@code --record run.mcap} writes what every source and
 * chain produced to an MCAP file, with the run's arguments ({@link RunArguments}); with {@code
 * --remote}, what this process hosts, to be merged with the worker's file ({@code
 * dev.prime.mcap.McapMerge}). {@code --replay run.mcap} drives a fresh controller, on any media,
 * with the encoder readings of such a file, towards the recorded goal unless {@code --goal} says
 * otherwise, and prints the recorded run's trace (see {@link RobotSimulation#replay}).
 *
 * <p>Exit codes: 0 the goal was reached (or help was printed), 1 it was not reached in the
 * allowed steps (or in the replayed readings), 2 the command line is wrong, 3 the Redis given by
 * {@code --redis} cannot be reached, 4 the recording cannot be written or replayed.
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
    String fromRecording = "";
    if (options.replay() != null) {
      try {
        RunArguments.Replay replay = RunArguments.forReplay(options);
        options = replay.options();
        fromRecording = replay.describe();
      } catch (IOException
          | UncheckedIOException
          | IllegalArgumentException
          | McapFormatException e) {
        err.println("error: cannot replay " + options.replay() + ": " + e.getMessage());
        return 4;
      }
    }
    Mission mission = options.mission();
    if (options.replay() != null) {
      out.printf(
          Locale.ROOT,
          "robot on media %s: replaying the %s of %s, driving from %s to %s, dt %.0f ms%n",
          options.media().cliName(),
          RobotController.ENCODERS,
          options.replay(),
          Pose.ORIGIN,
          mission.goal(),
          Mission.DT * 1000);
      if (!fromRecording.isEmpty()) {
        out.println(fromRecording);
      }
    } else {
      out.printf(
          Locale.ROOT,
          "robot on media %s: driving from %s to %s, dt %.0f ms, at most %d steps%n",
          options.media().cliName(),
          Pose.ORIGIN,
          mission.goal(),
          Mission.DT * 1000,
          mission.maxSteps());
    }
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
    if (options.replay() != null) {
      return replay(created, options.replay(), mission, out, err);
    }
    SimulationResult result;
    try (PrimeCore core = created) {
      McapRecorder recorder = null;
      if (options.record() != null) {
        recorder =
            startRecording(
                core.recording(),
                options.record(),
                Map.of(RunArguments.METADATA, RunArguments.of(options)),
                err);
        if (recorder == null) {
          return 4;
        }
      }
      try {
        result = new RobotSimulation(RobotSpec.SMALL_INDOOR).run(core, mission, out);
      } catch (RuntimeException | Error e) {
        if (recorder != null) {
          finishAfterFailure(recorder, e);
        }
        throw e;
      }
      if (recorder != null && !finishRecording(recorder, out, err)) {
        return 4;
      }
    }
    out.println(summary(result, mission));
    return result.reached() ? 0 : 1;
  }

  /**
   * Starts streaming every value the core records to {@code file} (rotation off, the writer's
   * default bounded queue: a disk that cannot keep up drops values, counted, never stalling the
   * robot), with Metadata records (the run's arguments).
   *
   * @return the recorder, or null (after saying why on {@code err}) if the file cannot be opened
   */
  static McapRecorder startRecording(
      Recording recording, Path file, Map<String, Map<String, String>> metadata, PrintStream err) {
    try {
      return RecordingMcap.stream(recording, file, McapWriterOptions.defaults(), Map.of(), metadata);
    } catch (IOException | UncheckedIOException | IllegalArgumentException e) {
      err.println("error: cannot write the recording to " + file + ": " + e.getMessage());
      return null;
    }
  }

  /**
   * Finishes a streamed recording after the run failed, so that the file is complete (readable
   * without {@code McapReader.openUnfinished}) and its path free for the next run; a failure to
   * finish it is added to {@code failure}'s.
   */
  private static void finishAfterFailure(McapRecorder recorder, Throwable failure) {
    try {
      recorder.close();
    } catch (IOException | RuntimeException e) {
      failure.addSuppressed(e);
    }
  }

  /**
   * Finishes a streamed recording and says what it wrote and what it lost.
   *
   * @return false (after saying why on {@code err}) if the file could not be written
   */
  static boolean finishRecording(McapRecorder recorder, PrintStream out, PrintStream err) {
    try {
      recorder.close();
    } catch (IOException | UncheckedIOException e) {
      err.println("error: cannot write the recording to " + recorder.files() + ": " + e.getMessage());
      return false;
    }
    Recording recording = recorder.recording();
    out.println(
        "recorded "
            + recorder.writtenCount()
            + " values to "
            + recorder.files().stream().map(Path::toString).collect(Collectors.joining(", "))
            + (recorder.droppedCount() + recorder.unwritableCount() == 0
                ? ""
                : " (lost " + recorder.droppedCount() + " the disk could not keep up with, "
                    + recorder.unwritableCount() + " unwritable)")
            + ": "
            + recording.names().stream()
                .filter(name -> recording.recorded(name) > 0)
                .map(name -> name + " " + recording.recorded(name))
                .collect(Collectors.joining(", ")));
    return true;
  }

  /**
   * Writes a recording with Metadata records (the run's arguments: {@link RunArguments}) and
   * says what it wrote: the values written per channel, and how many a full ring dropped before
   * (those are not in the file).
   *
   * @return false (after saying why on {@code err}) if the file cannot be written
   */
  static boolean record(
      Recording recording,
      Path file,
      Map<String, Map<String, String>> metadata,
      PrintStream out,
      PrintStream err) {
    Map<String, Integer> held = new LinkedHashMap<>(); // what the file gets per name
    for (String name : recording.names()) {
      held.put(name, recording.getAll(name).size());
    }
    long written;
    try {
      written = RecordingMcap.write(recording, file, Map.of(), metadata);
    } catch (IOException | UncheckedIOException | IllegalArgumentException e) {
      err.println("error: cannot write the recording to " + file + ": " + e.getMessage());
      return false;
    }
    out.println(
        "recorded "
            + written
            + " values to "
            + file
            + ": "
            + held.entrySet().stream()
                .filter(channel -> recording.recorded(channel.getKey()) > 0)
                .map(channel -> written(channel.getKey(), channel.getValue(), recording))
                .collect(Collectors.joining(", ")));
    return true;
  }

  /** "name N" for the N values of a channel in the file, with what its full ring dropped. */
  private static String written(String name, int held, Recording recording) {
    long dropped = recording.dropped(name);
    return name + " " + held + (dropped == 0 ? "" : " (" + dropped + " dropped)");
  }

  private static int replay(
      PrimeCore created, Path file, Mission mission, PrintStream out, PrintStream err) {
    ReplayedRun result;
    try (PrimeCore core = created) {
      result = new RobotSimulation(RobotSpec.SMALL_INDOOR).replay(core, mission, file, out);
    } catch (IOException | IllegalArgumentException e) {
      err.println("error: cannot replay " + file + ": " + e.getMessage());
      return 4;
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
      err.println("error: interrupted while replaying " + file);
      return 4;
    }
    out.println(
        String.join(
            System.lineSeparator(),
            String.format(
                Locale.ROOT,
                "%s goal %s after %d of %d recorded encoder readings (%.2f s simulated)",
                result.reached() ? "reached" : "did NOT reach",
                mission.goal(),
                result.steps(),
                result.readings(),
                result.steps() * Mission.DT),
            "  pose (odometry)   " + result.estimated(),
            String.format(
                Locale.ROOT,
                "  distance error to goal: %.4f m by odometry (tolerance %.2f m)",
                result.estimatedError(),
                RobotController.TOLERANCE)));
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

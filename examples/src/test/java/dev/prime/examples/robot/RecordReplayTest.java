package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNotEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import com.fasterxml.jackson.databind.JsonNode;
import com.fasterxml.jackson.databind.ObjectMapper;
import dev.prime.PrimeCore;
import dev.prime.Recording;
import dev.prime.mcap.ChannelInfo;
import dev.prime.mcap.McapReader;
import dev.prime.mcap.McapWriter;
import dev.prime.mcap.McapWriterOptions;
import dev.prime.mcap.PythonMcapCheck;
import dev.prime.mcap.RecordingMcap;
import java.io.ByteArrayOutputStream;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.nio.file.Path;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.TreeMap;
import java.util.concurrent.TimeUnit;
import java.util.regex.Matcher;
import java.util.regex.Pattern;
import org.junit.jupiter.api.BeforeAll;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.Timeout;
import org.junit.jupiter.api.io.TempDir;
import org.junit.jupiter.params.ParameterizedTest;
import org.junit.jupiter.params.provider.ValueSource;

/**
 * {@code --record} and {@code --replay}: a run recorded on Optimus (embedded Redis) and replayed on
 * Liberty prints the same trace, every step, and so does a run recorded on Liberty or Radiant and
 * replayed on Optimus; the file is checked by an independent MCAP reader.
 */
class RecordReplayTest {
  private static final String GOAL = "1,0.5";

  @TempDir static Path dir;

  private static Path recorded;
  private static String recordRun;

  /** A run's exit code, standard output and standard error. */
  record Run(int code, String out, String err) {
    List<String> trace() {
      return out.lines().filter(line -> line.startsWith("step ")).toList();
    }
  }

  static Run main(String... args) {
    ByteArrayOutputStream out = new ByteArrayOutputStream();
    ByteArrayOutputStream err = new ByteArrayOutputStream();
    int code =
        RobotMain.run(
            args,
            new PrintStream(out, true, StandardCharsets.UTF_8),
            new PrintStream(err, true, StandardCharsets.UTF_8));
    return new Run(code, out.toString(StandardCharsets.UTF_8), err.toString(StandardCharsets.UTF_8));
  }

  @BeforeAll
  static void recordOnOptimus() {
    recorded = dir.resolve("run.mcap");
    Run run =
        main("--media", "optimus", "--goal", GOAL, "--trace-every", "1", "--record", recorded.toString());
    assertEquals(0, run.code(), run.out() + run.err());
    recordRun = run.out();
  }

  @Test
  void aRunRecordedOnOptimusReplaysOnLibertyWithTheSameTraceEveryStep() {
    Run recordedRun = new Run(0, recordRun, "");
    Run replay = main("--media", "liberty", "--goal", GOAL, "--trace-every", "1", "--replay", recorded.toString());

    assertEquals(0, replay.code(), replay.out() + replay.err());
    List<String> trace = recordedRun.trace();
    assertTrue(trace.size() > 50, "a trace line per step: " + trace.size());
    assertTrue(trace.get(trace.size() - 1).endsWith("arrived"), trace.get(trace.size() - 1));
    assertEquals(trace, replay.trace());
    assertTrue(
        replay.out().contains("reached goal " + new Goal(1, 0.5) + " after " + trace.size() + " of " + trace.size()
            + " recorded encoder readings"),
        replay.out());
    assertTrue(recordRun.contains("recorded "), recordRun);
  }

  @ParameterizedTest
  @ValueSource(strings = {"liberty", "radiant"})
  void aRunRecordedOnAnInMemoryMediaReplaysOnOptimusWithTheSameTraceEveryStep(String media) {
    Path file = dir.resolve(media + ".mcap");
    Run run = main("--media", media, "--goal", GOAL, "--trace-every", "1", "--record", file.toString());
    assertEquals(0, run.code(), run.out() + run.err());
    assertTrue(run.out().contains(" to " + file + ": encoders "), run.out());
    assertEquals(new Run(0, recordRun, "").trace(), run.trace(), "the same run as on Optimus");

    Run replay = main("--media", "optimus", "--replay", file.toString());

    assertEquals(0, replay.code(), replay.out() + replay.err());
    assertTrue(replay.out().contains("  from the recording: --goal 1.0,0.5 --steps 3000 --trace-every 1"), replay.out());
    assertEquals(run.trace(), replay.trace());
  }

  @Test
  void aReplayWithoutGoalOrTraceIntervalTakesThemFromTheFile() throws Exception {
    try (McapReader reader = McapReader.open(recorded)) {
      Map<String, String> run = reader.metadata(RunArguments.METADATA).get(0);
      assertEquals("1.0,0.5", run.get("goal"));
      assertEquals("1", run.get("trace_every"));
      assertEquals("optimus", run.get("media"));
    }

    Run replay = main("--media", "radiant", "--replay", recorded.toString());

    assertEquals(0, replay.code(), replay.out() + replay.err());
    assertTrue(replay.out().contains("  from the recording: --goal 1.0,0.5 --steps 3000 --trace-every 1"), replay.out());
    assertEquals(new Run(0, recordRun, "").trace(), replay.trace());
  }

  @Test
  void aReplayWithoutStepsTakesThemFromTheFileAndTheUsageSaysSo() {
    Path file = dir.resolve("short.mcap");
    Run run = main("--steps", "20", "--trace-every", "1", "--record", file.toString());
    assertEquals(1, run.code(), "20 steps do not reach the goal: " + run.out());
    assertEquals(20, run.trace().size(), run.out());

    Run replay = main("--replay", file.toString());

    assertEquals(1, replay.code(), replay.out());
    assertTrue(replay.out().contains("  from the recording: --goal 2.0,1.0 --steps 20 --trace-every 1"), replay.out());
    assertEquals(run.trace(), replay.trace());
    assertTrue(RobotOptions.USAGE.contains("the recorded run's --goal, --steps and --trace-every unless given"),
        RobotOptions.USAGE);
  }

  @Test
  void aReplayStopsAfterTheStepsGiven() {
    List<String> trace = new Run(0, recordRun, "").trace();
    int steps = 10;
    assertTrue(trace.size() > steps, "the recorded run took more steps: " + trace.size());

    Run replay =
        main("--media", "liberty", "--steps", String.valueOf(steps), "--trace-every", "1", "--replay", recorded.toString());

    assertEquals(1, replay.code(), "stopped before the goal: " + replay.out());
    assertEquals(trace.subList(0, steps), replay.trace());
    assertTrue(
        replay.out().contains("did NOT reach goal " + new Goal(1, 0.5) + " after " + steps + " of " + trace.size()
            + " recorded encoder readings"),
        replay.out());
  }

  @Test
  void aReplayWithAnotherGoalIsKnowinglyDifferent() {
    Run replay = main("--media", "liberty", "--goal", "1,-0.5", "--trace-every", "1", "--replay", recorded.toString());

    List<String> trace = new Run(0, recordRun, "").trace();
    // the same readings: the first estimate is the same, the planner's volts are not
    assertEquals(trace.get(0).substring(0, 40), replay.trace().get(0).substring(0, 40));
    assertNotEquals(trace, replay.trace());
    assertEquals(1, replay.code(), "the recorded readings never bring it to the other goal: " + replay.out());
  }

  @Test
  void aFileWithoutEncodersIsRefusedNamingItsChannels() throws Exception {
    Path other = dir.resolve("other.mcap");
    try (McapWriter writer = McapWriter.open(other, McapWriterOptions.defaults().synchronous())) {
      writer.channel("poses", Pose.class).write(1, 1, 0, Pose.ORIGIN);
    }

    Run replay = main("--replay", other.toString());

    assertEquals(4, replay.code(), replay.out());
    assertTrue(replay.err().contains("no channel [encoders] in it; its channels: [poses]"), replay.err());
  }

  /**
   * The file the command line wrote with {@code --record} (with its {@code robot.run} Metadata
   * record) read by the Python {@code mcap} package: the channels and counts the run printed, every
   * message valid against its schema, the summary intact.
   */
  @Test
  @Timeout(value = 6, unit = TimeUnit.MINUTES) // a first pip install may take minutes
  void anIndependentReaderReadsTheFileTheCommandLineWrote() throws Exception {
    PythonMcapCheck python = PythonMcapCheck.installOrSkip();
    try (McapReader reader = McapReader.open(recorded)) {
      assertEquals(1, reader.metadata(RunArguments.METADATA).size(), "the run's arguments are in it");
    }
    Matcher said = Pattern.compile("recorded (\\d+) values to .*: (.*)").matcher(recordRun);
    assertTrue(said.find(), recordRun);
    Map<String, Long> printed = new TreeMap<>();
    for (String channel : said.group(2).strip().split(", ")) {
      String[] nameAndCount = channel.split(" ");
      printed.put(nameAndCount[0], Long.parseLong(nameAndCount[1]));
    }
    assertTrue(printed.keySet().containsAll(List.of("encoders", "odometry", "planner", "pid")), printed.toString());

    JsonNode check = python.check(recorded, dir);

    Map<String, Long> read = new TreeMap<>();
    check.get("channels").properties().forEach(e -> read.put(e.getKey(), e.getValue().get("read_count").asLong()));
    assertEquals(printed, read, check.toString());
    assertEquals(Long.parseLong(said.group(1)), check.get("message_count").asLong());
    assertEquals(List.of(), new ObjectMapper().convertValue(check.get("schema_errors"), List.class));
    assertTrue(check.get("log_time_sorted").asBoolean(), check.toString());
    assertTrue(check.get("summary_crc_ok").asBoolean(), check.toString());
  }

  /**
   * The robot's recording read by the Python {@code mcap} package: one channel per recorded
   * service, each with as many messages as the core recorded under that name, each valid against
   * its JSON Schema.
   */
  @Test
  @Timeout(value = 6, unit = TimeUnit.MINUTES) // a first pip install may take minutes
  void anIndependentReaderFindsOneChannelPerRecordedServiceWithItsCount() throws Exception {
    PythonMcapCheck python = PythonMcapCheck.installOrSkip();
    RobotOptions options = RobotOptions.parse("--media", "optimus", "--goal", GOAL, "--record", "x.mcap");
    Path file = dir.resolve("checked.mcap");
    Map<String, Long> counts = new TreeMap<>();
    long written;
    try (PrimeCore core = Media.OPTIMUS.create(options.coreConfig())) {
      SimulationResult result =
          new RobotSimulation(RobotSpec.SMALL_INDOOR)
              .run(core, options.mission(), new PrintStream(new ByteArrayOutputStream(), true, StandardCharsets.UTF_8));
      assertTrue(result.reached(), result.toString());
      Recording recording = core.recording();
      for (String name : recording.names()) {
        if (recording.recorded(name) > 0) {
          counts.put(name, recording.recorded(name));
        }
        assertEquals(0, recording.dropped(name), name);
      }
      written = RecordingMcap.write(recording, file);
      assertEquals(result.steps(), recording.recorded(RobotController.ENCODERS));
    }
    assertTrue(counts.keySet().containsAll(List.of("encoders", "odometry", "planner", "pid")), counts.toString());

    JsonNode check = python.check(file, dir);

    Map<String, Long> statistics = new TreeMap<>();
    Map<String, Long> read = new TreeMap<>();
    check.get("channels").properties().forEach(e -> {
      statistics.put(e.getKey(), e.getValue().get("statistics_count").asLong());
      read.put(e.getKey(), e.getValue().get("read_count").asLong());
    });
    assertEquals(counts, statistics, check.toString());
    assertEquals(counts, read);
    assertEquals(written, check.get("message_count").asLong());
    assertEquals(List.of(), new ObjectMapper().convertValue(check.get("schema_errors"), List.class));
    assertTrue(check.get("log_time_sorted").asBoolean());
    try (McapReader reader = McapReader.open(file)) {
      Map<String, String> services = new LinkedHashMap<>();
      for (ChannelInfo channel : reader.channels()) {
        services.put(channel.topic(), channel.metadata().get("prime.service"));
      }
      services.forEach((topic, service) -> assertEquals(topic, service));
    }
  }
}

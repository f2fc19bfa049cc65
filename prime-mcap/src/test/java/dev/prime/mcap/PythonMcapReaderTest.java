package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import com.fasterxml.jackson.databind.JsonNode;
import com.fasterxml.jackson.databind.ObjectMapper;
import dev.prime.Token;
import dev.prime.Tuple2;
import java.io.IOException;
import java.io.InputStream;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.nio.file.StandardCopyOption;
import java.util.List;
import java.util.Map;
import java.util.Optional;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Assumptions;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.Timeout;
import org.junit.jupiter.api.io.TempDir;

/**
 * An independent reader: the Python {@code mcap} package (with {@code jsonschema}) reads a file
 * the Java writer wrote. It runs for real wherever python3 and pip can reach PyPI: the test
 * installs both packages, pinned, into {@code target/python-mcap} (once per build directory);
 * without python3, or when pip cannot install them, it is skipped with the reason. The system
 * property {@code prime.mcap.python} names another interpreter.
 */
class PythonMcapReaderTest {
  private static final String MCAP = "mcap==1.6.0";
  private static final String JSONSCHEMA = "jsonschema==4.26.0";
  private static final String PYTHON = System.getProperty("prime.mcap.python", "python3");

  @TempDir Path dir;

  enum Mode { IDLE, DRIVING }

  record Pose(double x, double y, double theta) {}

  record Status(Mode mode, Optional<Pose> target, List<Integer> faults, Map<String, Double> gains, byte[] blob) {}

  @Test
  @Timeout(value = 6, unit = TimeUnit.MINUTES) // a first pip install may take minutes; then it is skipped
  void pythonMcapReadsOneChannelPerTopicWithTheRightCountsAndValidJson() throws Exception {
    Path packages = installPythonPackages();
    Path file = dir.resolve("robot.mcap");
    int poses = 500;
    int statuses = 120;
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().chunkSize(4096))) {
      McapChannel<Pose> odometry = writer.channel("odometry", Pose.class);
      McapChannel<Status> status = writer.channel("status", Status.class);
      McapChannel<Tuple2<Double, String>> labels = writer.channel("labels", new ValueType<Tuple2<Double, String>>() {});
      McapChannel<Token> ticks = writer.channel("ticks", Token.class);
      writer.channel("silent", Pose.class);
      for (int i = 0; i < poses; i++) {
        assertTrue(odometry.write(1_000_000L * i + 7, 1_000_000L * i, i, new Pose(i * 0.01, -i * 0.02, i % 7)));
        if (i % 5 == 0) {
          // written later than its log time: the files' chunks overlap in time
          status.write(1_000_000L * i, 1_000_000L * i, i / 5, new Status(
              i % 2 == 0 ? Mode.IDLE : Mode.DRIVING,
              i % 3 == 0 ? Optional.empty() : Optional.of(new Pose(1, 2, 3)),
              List.of(i, i + 1), Map.of("kp", 0.5 * i), new byte[] {1, 2, (byte) i}));
        }
        if (i % 100 == 0) {
          labels.write(1_000_000L * i + 3, 1_000_000L * i + 3, i, new Tuple2<>(i * 1.5, "label " + i));
        }
      }
      for (int i = 0; i < 20; i++) {
        ticks.write(1_000_000L * (poses + i), 1_000_000L * (poses + i), i, Token.INSTANCE);
      }
      for (int i = poses; i < poses + statuses - 100; i++) {
        status.write(1_000_000L * i, 1_000_000L * i, i, new Status(Mode.DRIVING, Optional.empty(), List.of(), Map.of(), new byte[0]));
      }
      assertEquals(0, writer.droppedCount());
    }

    JsonNode result = runCheck(packages, file);
    JsonNode channels = result.get("channels");
    assertEquals(5, channels.size(), result.toString());
    assertCounts(channels, "odometry", poses);
    assertCounts(channels, "status", statuses);
    assertCounts(channels, "labels", 5);
    assertCounts(channels, "ticks", 20);
    assertCounts(channels, "silent", 0);
    assertEquals(poses + statuses + 5 + 20, result.get("message_count").asLong());
    assertTrue(result.get("chunk_count").asInt() > 10, "several chunks: " + result.get("chunk_count"));
    assertEquals(result.get("chunk_count").asInt(), result.get("chunk_indexes").asInt());
    assertEquals(List.of(), new ObjectMapper().convertValue(result.get("schema_errors"), List.class),
        "every message matches its channel's JSON Schema");
    assertTrue(result.get("log_time_sorted").asBoolean());
    assertTrue(result.get("summary_crc_ok").asBoolean());
    // Schema, Channel, Statistics, ChunkIndex, MetadataIndex: each group spanned exactly
    assertEquals(List.of(0x03, 0x04, 0x0B, 0x08, 0x0D),
        new ObjectMapper().convertValue(result.get("summary_offset_groups"), List.class));
    assertEquals(result.get("chunk_count").asInt(), result.get("streamed_chunks").asInt());
    assertEquals(poses + statuses + 5 + 20, result.at("/stream_records/Message").asInt());
    assertEquals(1, result.at("/stream_records/DataEnd").asInt());
    assertEquals("prime-mcap", result.get("library").asText());

    assertEquals("json", channels.at("/odometry/message_encoding").asText());
    assertEquals("jsonschema", channels.at("/odometry/schema_encoding").asText());
    assertEquals(ValueType.of(Pose.class).name(), channels.at("/odometry/schema_name").asText());
    assertEquals(0.0, channels.at("/odometry/first/x").asDouble());
    assertEquals(0.0, channels.at("/labels/first/first").asDouble());
    assertEquals("label 0", channels.at("/labels/first/second").asText());
    assertEquals("INSTANCE", channels.at("/ticks/first").asText());
    assertEquals("IDLE", channels.at("/status/first/mode").asText());
    assertEquals("AQIA", channels.at("/status/first/blob").asText());
  }

  private static void assertCounts(JsonNode channels, String topic, int expected) {
    JsonNode channel = channels.get(topic);
    assertTrue(channel.get("rejects_probe").asBoolean(), topic + "'s schema rejects a wrong value");
    assertEquals(expected, channel.get("statistics_count").asInt(), topic + " in the statistics");
    assertEquals(expected, channel.get("read_count").asInt(), topic + " read by iter_messages");
  }

  private JsonNode runCheck(Path packages, Path file) throws IOException, InterruptedException {
    Path script = dir.resolve("check_mcap.py");
    try (InputStream in = getClass().getResourceAsStream("check_mcap.py")) {
      Files.copy(in, script, StandardCopyOption.REPLACE_EXISTING);
    }
    ProcessBuilder builder = new ProcessBuilder(PYTHON, script.toString(), file.toString());
    builder.environment().put("PYTHONPATH", packages.toString());
    Path output = dir.resolve("check.out");
    Path errors = dir.resolve("check.err");
    builder.redirectOutput(output.toFile()).redirectError(errors.toFile());
    Process process = builder.start();
    if (!process.waitFor(90, TimeUnit.SECONDS)) {
      process.destroyForcibly();
      throw new AssertionError("the Python check did not finish in 90 s");
    }
    String err = Files.readString(errors, StandardCharsets.UTF_8);
    assertEquals(0, process.exitValue(), "the Python mcap reader failed on the Java writer's file:\n" + err);
    return new ObjectMapper().readTree(Files.readString(output, StandardCharsets.UTF_8));
  }

  /** Installs mcap and jsonschema into target/python-mcap, or skips the test saying why. */
  private static Path installPythonPackages() throws IOException, InterruptedException {
    Path target = Path.of(System.getProperty("basedir", ".")).resolve("target").resolve("python-mcap");
    Path marker = target.resolve(".installed-" + MCAP + "-" + JSONSCHEMA);
    Process version = start(List.of(PYTHON, "--version"), null);
    if (version == null || !version.waitFor(30, TimeUnit.SECONDS) || version.exitValue() != 0) {
      Assumptions.abort(PYTHON + " is not on the PATH: the independent check with the Python mcap package is skipped");
    }
    if (Files.exists(marker)) {
      return target;
    }
    Files.createDirectories(target);
    Path log = target.resolveSibling("python-mcap-pip.log");
    Process pip = start(List.of(PYTHON, "-m", "pip", "install", "--quiet", "--disable-pip-version-check",
        "--no-input", "--retries", "1", "--timeout", "30", "--upgrade", "--target", target.toString(),
        MCAP, JSONSCHEMA), log);
    boolean finished = pip.waitFor(240, TimeUnit.SECONDS);
    if (!finished) {
      pip.destroyForcibly();
    }
    if (!finished || pip.exitValue() != 0) {
      String output = Files.exists(log) ? Files.readString(log, StandardCharsets.UTF_8) : "";
      Assumptions.abort("pip could not install " + MCAP + " and " + JSONSCHEMA + " (no pip, or PyPI"
          + " unreachable), so the independent check is skipped; pip said:\n" + output);
    }
    Files.createFile(marker);
    return target;
  }

  private static Process start(List<String> command, Path log) throws IOException {
    ProcessBuilder builder = new ProcessBuilder(command).redirectErrorStream(true);
    if (log != null) {
      builder.redirectOutput(log.toFile());
    } else {
      builder.redirectOutput(ProcessBuilder.Redirect.DISCARD);
    }
    try {
      return builder.start();
    } catch (IOException e) {
      return null;
    }
  }
}

package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import com.fasterxml.jackson.databind.JsonNode;
import com.fasterxml.jackson.databind.ObjectMapper;
import dev.prime.Token;
import dev.prime.Tuple2;
import java.nio.file.Path;
import java.util.List;
import java.util.Map;
import java.util.Optional;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.Timeout;
import org.junit.jupiter.api.io.TempDir;

/**
 * An independent reader: the Python {@code mcap} package (with {@code jsonschema}) reads a file
 * the Java writer wrote. It runs for real wherever python3 and pip can reach PyPI (see {@link
 * PythonMcapCheck}); otherwise it is skipped with the reason.
 */
class PythonMcapReaderTest {
  @TempDir Path dir;

  enum Mode { IDLE, DRIVING }

  record Pose(double x, double y, double theta) {}

  record Status(Mode mode, Optional<Pose> target, List<Integer> faults, Map<String, Double> gains, byte[] blob) {}

  @Test
  @Timeout(value = 6, unit = TimeUnit.MINUTES) // a first pip install may take minutes; then it is skipped
  void pythonMcapReadsOneChannelPerTopicWithTheRightCountsAndValidJson() throws Exception {
    PythonMcapCheck python = PythonMcapCheck.installOrSkip();
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

    JsonNode result = python.check(file, dir);
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
    assertEquals("INSTANCE", channels.at("/ticks/first/value").asText()); // wrapped for Foxglove
    assertEquals("IDLE", channels.at("/status/first/mode").asText());
    assertEquals("AQIA", channels.at("/status/first/blob").asText());
  }

  private static void assertCounts(JsonNode channels, String topic, int expected) {
    JsonNode channel = channels.get(topic);
    assertTrue(channel.get("rejects_probe").asBoolean(), topic + "'s schema rejects a wrong value");
    assertEquals(expected, channel.get("statistics_count").asInt(), topic + " in the statistics");
    assertEquals(expected, channel.get("read_count").asInt(), topic + " read by iter_messages");
  }
}

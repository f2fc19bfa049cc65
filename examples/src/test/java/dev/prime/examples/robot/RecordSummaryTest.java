package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.RecordingOptions;
import dev.prime.liberty.LibertyCore;
import dev.prime.mcap.McapReader;
import java.io.ByteArrayOutputStream;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.nio.file.Path;
import java.util.Map;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/** What {@code --record} says it wrote: the values in the file per channel, and what was dropped. */
class RecordSummaryTest {
  @TempDir Path dir;

  @Test
  void saysWhatTheFileHoldsPerChannelAndWhatAFullRingDropped() throws Exception {
    int capacity = 5;
    int published = 8;
    Path file = dir.resolve("run.mcap");
    ByteArrayOutputStream out = new ByteArrayOutputStream();
    ByteArrayOutputStream err = new ByteArrayOutputStream();
    try (PrimeCore core =
        new LibertyCore(
            CoreConfig.builder().recording(RecordingOptions.ring(capacity)).build())) {
      EventBlock<Integer> events = new EventBlock<>();
      core.source("numbers", events);
      core.start();
      for (int i = 1; i <= published; i++) {
        events.publish(i);
      }
      assertTrue(
          RobotMain.record(
              core.recording(),
              file,
              Map.of(),
              new PrintStream(out, true, StandardCharsets.UTF_8),
              new PrintStream(err, true, StandardCharsets.UTF_8)),
          err.toString(StandardCharsets.UTF_8));
    }
    assertEquals(
        "recorded 5 values to " + file + ": numbers 5 (3 dropped)",
        out.toString(StandardCharsets.UTF_8).strip());
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(capacity, reader.statistics().messageCount(), "values in the file");
    }
  }
}

package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.nio.file.Path;
import java.util.List;
import java.util.Map;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/** {@link McapWriter#metadata}: in every file of a rotated recording, names checked. */
class WriterMetadataTest {
  @TempDir Path dir;

  record Reading(long tick, String text) {}

  @Test
  void everyRotatedFileHasTheMetadataBeforeItsLossReport() throws Exception {
    Path first = dir.resolve("run.mcap");
    try (McapWriter writer = McapWriter.open(first, McapWriterOptions.defaults().chunkSize(256).rotateAtSize(2048))) {
      writer.metadata("robot.run", Map.of("goal", "1,0.5", "steps", "3000"));
      McapChannel<Reading> readings = writer.channel("readings", Reading.class);
      for (int i = 0; i < 200; i++) {
        assertTrue(readings.write(i, i, i, new Reading(i, "reading number " + i)));
      }
      writer.metadata("late", Map.of("added", "after the first files"));
    }
    List<Path> files = McapReader.recordingFiles(first);
    assertTrue(files.size() >= 3, "rotated: " + files);
    for (Path file : files) {
      try (McapReader reader = McapReader.open(file)) {
        assertEquals(List.of(Map.of("goal", "1,0.5", "steps", "3000")), reader.metadata("robot.run"), file.toString());
        assertEquals(McapWriter.LOSS_METADATA, reader.metadataNames().get(reader.metadataNames().size() - 1));
      }
    }
    try (McapReader last = McapReader.open(files.get(files.size() - 1))) {
      assertEquals(List.of("robot.run", "late", McapWriter.LOSS_METADATA), last.metadataNames());
    }
  }

  @Test
  void reservedOrEmptyNamesAndAClosedWriterAreRefused() throws Exception {
    McapWriter writer = McapWriter.open(dir.resolve("a.mcap"));
    assertThrows(IllegalArgumentException.class, () -> writer.metadata(McapWriter.LOSS_METADATA, Map.of()));
    assertThrows(IllegalArgumentException.class, () -> writer.metadata("", Map.of()));
    writer.close();
    IllegalStateException closed = assertThrows(IllegalStateException.class, () -> writer.metadata("x", Map.of()));
    assertTrue(closed.getMessage().contains("closed"), closed.getMessage());
  }
}

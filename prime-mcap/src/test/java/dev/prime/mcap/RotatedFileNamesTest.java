package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.IOException;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.List;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * A recording's rotated files are {@code run-0001.mcap}, {@code run-0002.mcap}, ... contiguous from
 * the first: a file whose name only looks like a rotated file's, further on (a user's
 * date-named {@code run-2026.mcap}), is no file of it, so it is neither listed nor deleted.
 */
class RotatedFileNamesTest {
  @TempDir Path dir;

  record Reading(int n) {}

  private static List<Path> record(Path file, int count) throws IOException {
    McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().chunkSize(512).rotateAtSize(1024));
    try {
      McapChannel<Reading> readings = writer.channel("readings", Reading.class);
      for (int i = 0; i < count; i++) {
        assertTrue(readings.write(i, i, i, new Reading(i)));
      }
    } finally {
      writer.close();
    }
    return writer.files();
  }

  @Test
  void filesNamedLikeRotatedFilesBeyondTheRecordingAreNeitherListedNorDeleted() throws IOException {
    Path file = dir.resolve("run.mcap");
    byte[] year = "the run of 2026, a recording of the user's own".getBytes(StandardCharsets.UTF_8);
    byte[] day = "the run of 29 November 2026".getBytes(StandardCharsets.UTF_8);
    Path yearFile = Files.write(dir.resolve("run-2026.mcap"), year); // the rotated-name width, 4 digits
    Path dayFile = Files.write(dir.resolve("run-20261129.mcap"), day);
    assertEquals(yearFile, McapWriter.rotatedPath(file, 2026), "named as rotated file 2026 would be");
    assertEquals(dayFile, McapWriter.rotatedPath(file, 20261129), "named as rotated file 20261129 would be");

    List<Path> earlier = record(file, 200);
    assertTrue(earlier.size() >= 3, "rotated into " + earlier);
    assertEquals(earlier, McapReader.recordingFiles(file), "the recording's files, contiguous from the first");

    List<Path> later = record(file, 20);
    assertTrue(later.size() < earlier.size(), later + " against " + earlier);
    assertEquals(later, McapReader.recordingFiles(file), "a new writer replaced the recording");
    assertArrayEquals(year, Files.readAllBytes(yearFile), "a new writer leaves run-2026.mcap as it was");
    assertArrayEquals(day, Files.readAllBytes(dayFile), "and run-20261129.mcap");

    Path input = dir.resolve("input.mcap");
    record(input, 10);
    McapMerge.merge(List.of(input), file);
    assertEquals(List.of(file), McapReader.recordingFiles(file), "the merge is the recording at run.mcap");
    assertArrayEquals(year, Files.readAllBytes(yearFile), "a merge leaves run-2026.mcap as it was");
    assertArrayEquals(day, Files.readAllBytes(dayFile), "and run-20261129.mcap");
    for (Path stale : earlier.subList(1, earlier.size())) {
      assertTrue(Files.notExists(stale), stale + " of the earlier recording is deleted");
    }

    // a date-named recording of its own is no rotated file of take.mcap: merged into it, it stays
    Path dated = dir.resolve("take-2026.mcap");
    record(dated, 10);
    McapMerge.merge(List.of(dated), dir.resolve("take.mcap"));
    assertEquals(List.of(dir.resolve("take.mcap")), McapReader.recordingFiles(dir.resolve("take.mcap")));
    try (McapReader reader = McapReader.open(dated)) {
      assertEquals(10, reader.messageCount("readings"), "the input is left as it was");
    }
  }

  /**
   * A file or two moved or deleted from the middle of a recording leaves a gap that {@link
   * McapReader#recordingFiles} refuses over (naming the missing file); a new writer at the path
   * deletes the earlier recording's files across such a gap too, so the new recording is listed,
   * not refused for the earlier one's leftovers. A gap of three names or more ends a recording.
   */
  @Test
  void aNewRecordingDeletesTheEarlierOnesFilesAcrossAGapTheReaderRefusesOver() throws IOException {
    Path file = dir.resolve("gap.mcap");
    List<Path> earlier = record(file, 300);
    assertTrue(earlier.size() >= 6, "rotated into " + earlier);
    Files.delete(earlier.get(2)); // gap-0002.mcap, moved away by hand
    assertThrows(IllegalStateException.class, () -> McapReader.recordingFiles(file), "a file of it is missing");

    List<Path> later = record(file, 1);
    assertEquals(List.of(file), later);
    assertEquals(later, McapReader.recordingFiles(file), "the new recording, not refused for the earlier one's files");
    for (Path stale : earlier.subList(1, earlier.size())) {
      assertTrue(Files.notExists(stale), stale + " of the earlier recording is deleted");
    }

    Path far = Files.write(McapWriter.rotatedPath(file, 4), new byte[] {1, 2, 3}); // past a gap of three names
    assertEquals(later, McapReader.recordingFiles(file), "a gap of three names ends the recording");
    record(file, 1);
    assertArrayEquals(new byte[] {1, 2, 3}, Files.readAllBytes(far), "and a writer leaves what is past it");
  }
}

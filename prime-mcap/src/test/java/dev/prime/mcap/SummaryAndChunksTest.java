package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.IOException;
import java.io.RandomAccessFile;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.Comparator;
import java.util.List;
import java.util.Map;
import java.util.stream.Collectors;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/** The summary section, chunking and the log-time merge, and rotation by size. */
class SummaryAndChunksTest {
  @TempDir Path dir;

  record Reading(int index, double value) {}

  /** Offset of the first chunk: the magic and the Header ("" profile, "prime-mcap" library). */
  private static final long FIRST_CHUNK = 8 + 9 + 4 + 4 + "prime-mcap".length();

  private static void overwrite(Path file, long from, long to, byte value) throws IOException {
    try (RandomAccessFile raf = new RandomAccessFile(file.toFile(), "rw")) {
      raf.seek(from);
      for (long i = from; i < to; i++) {
        raf.write(value);
      }
    }
  }

  @Test
  void statisticsAndChannelsComeFromTheSummaryWithoutReadingTheDataSection() throws IOException {
    Path file = dir.resolve("summary.mcap");
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().chunkSize(512))) {
      McapChannel<Reading> a = writer.channel("a", Reading.class);
      McapChannel<Double> b = writer.channel("b", Double.class);
      writer.channel("empty", ValueType.of(Reading.class), Map.of("unit", "m"));
      for (int i = 0; i < 300; i++) {
        a.write(10L * i, 10L * i, i, new Reading(i, i / 2.0));
        if (i % 3 == 0) {
          b.write(10L * i + 1, 10L * i + 1, i, i * 1.0);
        }
      }
    }
    long chunkCount;
    try (McapReader reader = McapReader.open(file)) {
      assertTrue(reader.statistics().chunkCount() > 5, "several chunks: " + reader.statistics().chunkCount());
      chunkCount = reader.statistics().chunkCount();
    }
    // Wipe the whole data section after the header: everything still known must come from the summary.
    long summaryStart = summaryStart(file);
    overwrite(file, FIRST_CHUNK, summaryStart, (byte) 0);

    try (McapReader reader = McapReader.open(file)) {
      assertTrue(reader.hasSummary());
      assertEquals(List.of("a", "b", "empty"),
          reader.channels().stream().map(ChannelInfo::topic).collect(Collectors.toList()));
      assertEquals(300, reader.messageCount("a"));
      assertEquals(100, reader.messageCount("b"));
      assertEquals(0, reader.messageCount("empty"));
      assertEquals(Map.of("unit", "m"), reader.channel("empty").orElseThrow().metadata());
      McapStatistics stats = reader.statistics();
      assertEquals(400, stats.messageCount());
      assertEquals(2, stats.schemaCount());
      assertEquals(3, stats.channelCount());
      assertEquals(chunkCount, stats.chunkCount());
      assertEquals(0, stats.messageStartTime());
      assertEquals(2990, stats.messageEndTime());
      assertEquals(1, stats.metadataCount());
      assertEquals(ValueType.of(Reading.class).jsonSchema(),
          reader.channel("a").orElseThrow().schema().orElseThrow().text());
      // and the wiped data is noticed as soon as it is read
      McapFormatException e = assertThrows(McapFormatException.class, () -> reader.messages().count());
      assertTrue(e.getMessage().contains("Chunk"), e.getMessage());
    }
  }

  private static long summaryStart(Path file) throws IOException {
    byte[] bytes = Files.readAllBytes(file);
    int footer = bytes.length - 8 - 29;
    return java.nio.ByteBuffer.wrap(bytes, footer + 9, 8).order(java.nio.ByteOrder.LITTLE_ENDIAN).getLong();
  }

  @Test
  void messagesFromOverlappingChunksComeBackInLogTimeOrder() throws IOException {
    Path file = dir.resolve("order.mcap");
    List<long[]> written = new ArrayList<>();
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().chunkSize(300))) {
      McapChannel<Reading> fast = writer.channel("fast", Reading.class);
      McapChannel<Reading> late = writer.channel("late", Reading.class);
      for (int i = 0; i < 400; i++) {
        fast.write(1000L * i, 1000L * i, i, new Reading(i, 0));
        written.add(new long[] {1000L * i, 0});
        if (i % 4 == 3) {
          // a slow sensor: recorded 150 ms after the time it stamps, so chunks overlap in time
          long t = 1000L * (i - 150) + 500;
          if (t >= 0) {
            late.write(t, t, i, new Reading(i, 1));
            written.add(new long[] {t, 1});
          }
        }
      }
    }
    written.sort(Comparator.comparingLong(w -> w[0]));
    try (McapReader reader = McapReader.open(file)) {
      assertTrue(reader.statistics().chunkCount() > 20, "chunks: " + reader.statistics().chunkCount());
      List<McapMessage> all = reader.messages().collect(Collectors.toList());
      assertEquals(written.size(), all.size());
      for (int k = 0; k < all.size(); k++) {
        assertEquals(written.get(k)[0], all.get(k).logTime(), "message " + k);
        assertEquals(written.get(k)[1] == 0 ? "fast" : "late", all.get(k).channel().topic());
      }
      List<Long> late = reader.messages("late", Reading.class).map(TypedMessage::logTime).collect(Collectors.toList());
      assertEquals(reader.messageCount("late"), late.size());
      assertEquals(late.stream().sorted().collect(Collectors.toList()), late);
    }
  }

  @Test
  void readingOneTopicSkipsTheChunksThatHaveNoneOfItsMessages() throws IOException {
    Path file = dir.resolve("skip.mcap");
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().chunkSize(200))) {
      McapChannel<Reading> first = writer.channel("first", Reading.class);
      McapChannel<Reading> second = writer.channel("second", Reading.class);
      for (int i = 0; i < 100; i++) {
        first.write(i, i, i, new Reading(i, 0));
      }
      for (int i = 100; i < 200; i++) {
        second.write(i, i, i, new Reading(i, 0));
      }
    }
    // corrupt a byte inside the records of the first chunk, which holds only "first" messages
    overwrite(file, FIRST_CHUNK + 60, FIRST_CHUNK + 61, (byte) 0x55);
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(100, reader.messages("second", Reading.class).count(),
          "the index says the corrupt chunk has no 'second' message, so it is never read");
      McapFormatException e = assertThrows(McapFormatException.class, () -> reader.messages("first").count());
      assertTrue(e.getMessage().contains("at byte " + FIRST_CHUNK + ": bad CRC"), e.getMessage());
    }
  }

  @Test
  void anEmptyRecordingIsAValidFile() throws IOException {
    Path file = dir.resolve("empty.mcap");
    McapWriter.open(file).close();
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(0, reader.statistics().messageCount());
      assertEquals(0, reader.statistics().chunkCount());
      assertEquals(List.of(), reader.channels());
      assertEquals(0, reader.messages().count());
      reader.verify();
    }
  }

  @Test
  void aRecordingWithAMissingMiddleFileIsRefusedNamingIt() throws IOException {
    Path file = dir.resolve("gap.run.mcap");
    List<Path> files = recordReadings(file, 600);
    assertTrue(files.size() >= 4, "rotated into " + files);
    Files.createFile(dir.resolve("gap.run-notes.mcap")); // not a file of the recording
    Files.createFile(dir.resolve("gap.run-0001.mcap.bak"));
    assertEquals(files, McapReader.recordingFiles(file), "other files of the folder are no part of it");

    Files.delete(files.get(1));
    IllegalStateException gap = assertThrows(IllegalStateException.class, () -> McapReader.recordingFiles(file));
    assertEquals(
        "file " + files.get(1) + " of the recording is missing, yet " + files.get(files.size() - 1)
            + " exists: a file of the recording was moved or deleted; put it back, or open the"
            + " files there are one by one with McapReader.open",
        gap.getMessage());
    Files.delete(file);
    assertThrows(IllegalStateException.class, () -> McapReader.recordingFiles(file), "the first missing");
    for (Path part : files.subList(2, files.size())) {
      Files.delete(part);
    }
    assertEquals(List.of(), McapReader.recordingFiles(file), "no file of the recording: none");
  }

  @Test
  void aNewRecordingAtAPathDeletesTheRotatedFilesOfAnEarlierOne() throws IOException {
    Path file = dir.resolve("again.mcap");
    List<Path> earlier = recordReadings(file, 600);
    assertTrue(earlier.size() >= 4, "rotated into " + earlier);
    Path unrelated = Files.createFile(dir.resolve("again-notes.mcap"));

    List<Path> later = recordReadings(file, 100);
    assertTrue(later.size() < earlier.size(), later + " against " + earlier);
    assertEquals(later, McapReader.recordingFiles(file), "the later recording's files only");
    for (Path stale : earlier.subList(later.size(), earlier.size())) {
      assertTrue(Files.notExists(stale), stale + " of the earlier recording is deleted");
    }
    assertTrue(Files.exists(unrelated), "a file not named as a rotated file stays");
    long count = 0;
    for (Path part : later) {
      try (McapReader reader = McapReader.open(part)) {
        count += reader.messageCount("readings");
      }
    }
    assertEquals(100, count, "the later recording's messages, none of the earlier one's");
  }

  /** Writes {@code count} readings to a recording rotated every 4 KiB; its files. */
  private static List<Path> recordReadings(Path file, int count) throws IOException {
    McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().chunkSize(1024).rotateAtSize(4096));
    try {
      McapChannel<Reading> readings = writer.channel("readings", Reading.class);
      for (int i = 0; i < count; i++) {
        assertTrue(readings.write(i, i, i, new Reading(i, i)));
      }
    } finally {
      writer.close();
    }
    return writer.files();
  }

  @Test
  void rotationBySizeWritesSelfContainedNumberedFiles() throws IOException {
    Path file = dir.resolve("run.mcap");
    int total = 3000;
    McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().chunkSize(4096).rotateAtSize(32 * 1024));
    try {
      McapChannel<Reading> readings = writer.channel("readings", Reading.class);
      writer.channel("unused", Double.class);
      for (int i = 0; i < total; i++) {
        assertTrue(readings.write(i, i, i, new Reading(i, Math.sqrt(i))));
      }
    } finally {
      writer.close();
    }
    List<Path> files = writer.files();
    assertTrue(files.size() >= 3, "rotated into " + files);
    assertEquals(files, McapReader.recordingFiles(file));
    for (int k = 0; k < files.size(); k++) {
      assertEquals(McapWriter.rotatedPath(file, k), files.get(k));
      assertTrue(Files.exists(files.get(k)));
    }
    assertEquals(dir.resolve("run-0001.mcap"), files.get(1));
    long next = 0;
    for (Path part : files) {
      assertTrue(Files.size(part) < 32 * 1024 + 4096 + 2048, part + " is " + Files.size(part) + " bytes");
      try (McapReader reader = McapReader.open(part)) {
        reader.verify();
        assertEquals(List.of("readings", "unused"),
            reader.channels().stream().map(ChannelInfo::topic).collect(Collectors.toList()),
            "each file names every channel");
        for (TypedMessage<Reading> m : (Iterable<TypedMessage<Reading>>) reader.messages("readings", Reading.class)::iterator) {
          assertEquals(next, m.value().index(), "no message lost or repeated across files");
          next++;
        }
        assertEquals("0", reader.metadata(McapWriter.LOSS_METADATA).get(0).get("dropped_messages"));
      }
    }
    assertEquals(total, next);
  }

  /**
   * A file is finished once it reaches the rotation size, and the next one is started by the next
   * message: a recording whose last message filled a file ends with that file, not with an empty
   * one made at close.
   */
  @Test
  void aRecordingEndsWithItsLastMessagesFileNotAnEmptyOne() throws IOException {
    for (boolean synchronous : new boolean[] {true, false}) {
      Path file = dir.resolve((synchronous ? "sync" : "queued") + ".mcap");
      McapWriterOptions options = McapWriterOptions.defaults().rotateAtSize(1);
      McapWriter writer = McapWriter.open(file, synchronous ? options.synchronous() : options);
      try {
        McapChannel<Reading> readings = writer.channel("readings", Reading.class);
        for (int i = 0; i < 3; i++) {
          assertTrue(readings.write(i, i, i, new Reading(i, i)));
        }
      } finally {
        writer.close();
      }
      List<Path> files = writer.files();
      assertEquals(List.of(file, McapWriter.rotatedPath(file, 1), McapWriter.rotatedPath(file, 2)), files,
          "one file per message, each filled by it");
      assertEquals(files, McapReader.recordingFiles(file));
      for (Path part : files) {
        try (McapReader reader = McapReader.open(part)) {
          assertEquals(1, reader.messageCount("readings"), part.toString());
          assertEquals("0", reader.metadata(McapWriter.LOSS_METADATA).get(0).get("dropped_messages"));
        }
      }
      assertTrue(Files.notExists(McapWriter.rotatedPath(file, 3)), "no empty file after the last message");
    }
  }

  /** A Metadata record added after the last file was finished still goes into a file of its own. */
  @Test
  void aMetadataRecordAddedAfterTheLastRotationGetsAFile() throws IOException {
    Path file = dir.resolve("late.mcap");
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().rotateAtSize(1).synchronous())) {
      assertTrue(writer.channel("readings", Reading.class).write(0, 0, 0, new Reading(0, 0)));
      writer.metadata("late", Map.of("added", "after the file was finished"));
    }
    assertEquals(List.of(file, McapWriter.rotatedPath(file, 1)), McapReader.recordingFiles(file));
    try (McapReader reader = McapReader.open(McapWriter.rotatedPath(file, 1))) {
      assertEquals(0, reader.messageCount("readings"));
      assertEquals(List.of(Map.of("added", "after the file was finished")), reader.metadata("late"));
    }
  }

  @Test
  void rotatedNamesFollowTheDocumentedRule() {
    assertEquals(Path.of("logs/run.mcap"), McapWriter.rotatedPath(Path.of("logs/run.mcap"), 0));
    assertEquals(Path.of("logs/run-0001.mcap"), McapWriter.rotatedPath(Path.of("logs/run.mcap"), 1));
    assertEquals(Path.of("run.2024.01-0012.mcap"), McapWriter.rotatedPath(Path.of("run.2024.01.mcap"), 12));
    assertEquals(Path.of("recording-12345"), McapWriter.rotatedPath(Path.of("recording"), 12345));
    assertEquals(Path.of(".hidden-0002"), McapWriter.rotatedPath(Path.of(".hidden"), 2));
  }

  @Test
  void oneTopicOneType() throws IOException {
    try (McapWriter writer = McapWriter.open(dir.resolve("topics.mcap"))) {
      McapChannel<Reading> readings = writer.channel("readings", Reading.class);
      assertTrue(readings == writer.channel("readings", Reading.class), "the same topic and type give the same channel");
      IllegalArgumentException e = assertThrows(IllegalArgumentException.class, () -> writer.channel("readings", Double.class));
      assertTrue(e.getMessage().contains("topic 'readings' already records"), e.getMessage());
      assertThrows(IllegalArgumentException.class, () -> readings.write(-1, 0, 0, new Reading(0, 0)));
      assertThrows(NullPointerException.class, () -> readings.write(0, 0, 0, null));
    }
  }
}

package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;
import static org.junit.jupiter.api.Assumptions.assumeTrue;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Recording;
import dev.prime.RecordingOptions;
import dev.prime.liberty.LibertyCore;
import java.io.IOException;
import java.io.UncheckedIOException;
import java.nio.ByteBuffer;
import java.nio.channels.FileChannel;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.nio.file.StandardOpenOption;
import java.util.ArrayList;
import java.util.List;
import java.util.Map;
import java.util.stream.Stream;
import org.junit.jupiter.api.BeforeEach;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * A disk that fills up while a file is written, after its Header: the failure names the file and
 * says what became of it, and no half-written file is left where a reader would take it for a
 * whole recording. The disk is Linux's {@code /dev/full}, whose writes fail with ENOSPC ("No space
 * left on device"): a file's first writes reach the file, the rest go to {@code /dev/full}.
 */
class DiskFullTest {
  @TempDir Path dir;

  record Reading(int value) {}

  private static final Path FULL = Path.of("/dev/full");

  @BeforeEach
  void needsDevFull() {
    assumeTrue(Files.isWritable(FULL), "needs Linux's /dev/full to fill a disk");
  }

  /**
   * Opens files for real; each file's first {@code passing} writes reach it (its magic and Header
   * are the first two), the ones after go to {@code /dev/full} and fail as on a full disk.
   */
  private static OutputOpener fullAfter(int passing) {
    return path -> {
      FileChannel file = OutputOpener.FILES.open(path);
      return new ForwardingFileChannel(file) {
        private int writes;

        @Override
        public int write(ByteBuffer source) throws IOException {
          if (writes++ < passing) {
            return super.write(source);
          }
          try (FileChannel full = FileChannel.open(FULL, StandardOpenOption.WRITE)) {
            return full.write(source);
          }
        }
      };
    };
  }

  private List<Path> filesIn() throws IOException {
    try (Stream<Path> files = Files.list(dir)) {
      return files.sorted().toList();
    }
  }

  private static Recording recorded(PrimeCore core, int values) {
    EventBlock<Integer> ticks = new EventBlock<>();
    core.source("ticks", ticks);
    core.start();
    for (int i = 0; i < values; i++) {
      ticks.publish(i);
    }
    return core.recording();
  }

  @Test
  void aRecordingWriteThatFillsTheDiskRemovesTheFileItCreated() throws Exception {
    Path file = dir.resolve("run.mcap");
    try (PrimeCore core = new LibertyCore(CoreConfig.builder().recording(RecordingOptions.ring(16)).build())) {
      Recording recording = recorded(core, 16);

      IOException e = assertThrows(IOException.class,
          () -> RecordingMcap.write(recording, file, Map.of(), Map.of(), fullAfter(2)));

      assertFalse(Files.exists(file), "no half-written file is left: " + e.getMessage());
      assertTrue(e.getMessage().contains(file.toString()) && e.getMessage().contains("No space left on device")
          && e.getMessage().contains("removed"), e.getMessage());
      assertEquals(List.of(), filesIn(), "nor a lock file");
    }
  }

  @Test
  void aRecordingWriteThatFillsTheDiskOverAnEarlierFileLeavesItEmptyAndSaysSo() throws Exception {
    Path file = dir.resolve("run.mcap");
    Files.writeString(file, "an earlier recording");
    try (PrimeCore core = new LibertyCore(CoreConfig.builder().recording(RecordingOptions.ring(16)).build())) {
      Recording recording = recorded(core, 16);

      IOException e = assertThrows(IOException.class,
          () -> RecordingMcap.write(recording, file, Map.of(), Map.of(), fullAfter(2)));

      assertEquals(0, Files.size(file), "no half-written MCAP file is left: " + e.getMessage());
      assertTrue(e.getMessage().contains(file.toString()) && e.getMessage().contains("No space left on device")
          && e.getMessage().contains("empty"), e.getMessage());
      assertEquals(List.of(file), filesIn(), "nor a lock file");
    }
  }

  /**
   * A path that is a symbolic link to a file not there yet: the write creates that file, so a
   * full disk removes it (the link is left as it was) and says so, not that an earlier file's
   * contents are gone.
   */
  @Test
  void aRecordingWriteThroughADanglingLinkThatFillsTheDiskRemovesTheFileItCreated() throws Exception {
    Path target = dir.resolve("run.mcap");
    Path link = dir.resolve("latest.mcap");
    try {
      Files.createSymbolicLink(link, target.getFileName());
    } catch (UnsupportedOperationException | IOException e) {
      assumeTrue(false, "no symbolic links here: " + e);
    }
    try (PrimeCore core = new LibertyCore(CoreConfig.builder().recording(RecordingOptions.ring(16)).build())) {
      Recording recording = recorded(core, 16);

      IOException e = assertThrows(IOException.class,
          () -> RecordingMcap.write(recording, link, Map.of(), Map.of(), fullAfter(2)));

      assertEquals(List.of(link), filesIn(), "the link alone, as before: no half-written file, nor an empty one: "
          + e.getMessage());
      assertTrue(Files.isSymbolicLink(link) && Files.readSymbolicLink(link).equals(target.getFileName()),
          "the link stays as it was");
      assertTrue(e.getMessage().contains("No space left on device") && e.getMessage().contains("removed")
          && !e.getMessage().contains("what it held before is gone"), e.getMessage());
    }
  }

  /**
   * A writer (the one {@link RecordingMcap#stream} records into) whose disk fills keeps what it
   * wrote, which {@link McapReader#openUnfinished} reads; its close says the file is unfinished.
   */
  @Test
  void aWriterWhoseDiskFillsSaysItsFileIsUnfinished() throws Exception {
    Path file = dir.resolve("stream.mcap");
    McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().chunkSize(1), fullAfter(8));
    McapChannel<Reading> readings = writer.channel("readings", Reading.class);
    for (int i = 0; i < 10; i++) {
      assertTrue(readings.write(i, i, i, new Reading(i)));
    }

    IOException e = assertThrows(IOException.class, writer::close);

    assertTrue(e.getMessage().contains(file.toString()) && e.getMessage().contains("No space left on device")
        && e.getMessage().contains("unfinished") && e.getMessage().contains("openUnfinished"), e.getMessage());
    try (McapReader reader = McapReader.openUnfinished(file)) {
      List<Integer> read = reader.messages("readings", Reading.class).map(m -> m.value().value()).toList();
      assertFalse(read.isEmpty(), "the chunks written before the disk filled are read");
      List<Integer> written = new ArrayList<>();
      for (int i = 0; i < read.size(); i++) {
        written.add(i);
      }
      assertEquals(written, read, "the first messages, in order");
    }
  }

  /** A synchronous writer's write that fills the disk says so, naming the file. */
  @Test
  void aSynchronousWriteThatFillsTheDiskNamesTheFile() throws Exception {
    Path file = dir.resolve("sync.mcap");
    McapWriter writer =
        McapWriter.open(file, McapWriterOptions.defaults().synchronous().chunkSize(1), fullAfter(2));
    McapChannel<Reading> readings = writer.channel("readings", Reading.class);

    UncheckedIOException e = assertThrows(UncheckedIOException.class, () -> readings.write(1, 1, 1, new Reading(1)));
    assertTrue(e.getMessage().contains(file.toString()) && e.getMessage().contains("No space left on device"),
        e.getMessage());
    IOException closed = assertThrows(IOException.class, writer::close);
    assertTrue(closed.getMessage().contains("unfinished"), closed.getMessage());
  }

  /** A merge whose disk fills names its output, leaves it as it was, and leaves nothing beside it. */
  @Test
  void aMergeThatFillsTheDiskLeavesTheOutputAsItWas() throws Exception {
    Path input = dir.resolve("robot.mcap");
    try (McapWriter writer = McapWriter.open(input, McapWriterOptions.defaults().synchronous())) {
      McapChannel<Reading> readings = writer.channel("readings", Reading.class);
      for (int i = 0; i < 100; i++) {
        assertTrue(readings.write(i, i, i, new Reading(i)));
      }
    }
    Path output = dir.resolve("run.mcap");
    byte[] earlier = "an earlier merge".getBytes(StandardCharsets.UTF_8);
    Files.write(output, earlier);
    List<Path> before = filesIn();

    IOException e = assertThrows(IOException.class,
        () -> McapMerge.merge(List.of(input), output, McapMerge.Options.defaults().chunkSize(64), fullAfter(4)));

    assertTrue(e.getMessage().contains(output.toString()) && e.getMessage().contains("No space left on device")
        && e.getMessage().contains("as it was"), e.getMessage());
    assertEquals(new String(earlier, StandardCharsets.UTF_8), Files.readString(output), "the output is as it was");
    assertEquals(before, filesIn(), "and nothing is left beside it");
  }
}

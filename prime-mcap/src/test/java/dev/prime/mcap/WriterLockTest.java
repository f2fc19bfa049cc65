package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;
import static org.junit.jupiter.api.Assumptions.assumeTrue;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.RecordingOptions;
import dev.prime.liberty.LibertyCore;
import java.io.BufferedReader;
import java.io.File;
import java.io.IOException;
import java.io.InputStreamReader;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.List;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * One writer per recording: a second {@link McapWriter} (or recorder) opened at the path of one
 * that is still writing, in the same JVM or in another process, is refused naming the path and
 * the writer that holds it, and leaves the first one's files as they were.
 */
class WriterLockTest {
  @TempDir Path dir;

  record Reading(int value) {}

  @Test
  void aSecondWriterInTheSameJvmIsRefusedNamingThePathAndTheHolder() throws IOException {
    Path file = dir.resolve("run.mcap");
    McapWriterOptions options = McapWriterOptions.defaults().synchronous().chunkSize(1).rotateAtSize(1);
    try (McapWriter first = McapWriter.open(file, options)) {
      McapChannel<Reading> readings = first.channel("readings", Reading.class);
      for (int i = 0; i < 3; i++) {
        assertTrue(readings.write(i, i, i, new Reading(i)));
      }
      long sizeBefore = Files.size(file);

      IOException refused = assertThrows(IOException.class, () -> McapWriter.open(file, options).close());

      String message = refused.getMessage();
      assertTrue(message.contains(file.toString()), message);
      assertTrue(message.contains("pid " + ProcessHandle.current().pid()), "names the holder: " + message);
      assertTrue(message.contains(Thread.currentThread().getName()), "names the holder's thread: " + message);
      assertEquals(sizeBefore, Files.size(file), "the first writer's file is not truncated");
      assertTrue(Files.exists(McapWriter.rotatedPath(file, 1)), "nor its rotated files deleted");
      assertTrue(readings.write(3, 3, 3, new Reading(3)), "the first writer goes on");
    }
    List<Path> files = McapReader.recordingFiles(file);
    long messages = 0;
    for (Path part : files) {
      try (McapReader reader = McapReader.open(part)) {
        messages += reader.messageCount("readings");
      }
    }
    assertEquals(4, messages, "every message of the first writer, none lost to the refused one");
    assertFalse(Files.exists(RecordingLock.lockPath(file)), "no lock file is left once the writer is closed");
    try (McapWriter again = McapWriter.open(file, options)) {
      assertEquals(List.of(file), again.files(), "a writer opens once the first one is closed");
    }
  }

  @Test
  void aRecorderIsRefusedWhileAWriterHoldsThePath() throws Exception {
    Path file = dir.resolve("recorder.mcap");
    try (PrimeCore core = new LibertyCore(CoreConfig.builder().recording(RecordingOptions.ring(4)).build());
        McapWriter writer = McapWriter.open(file)) {
      core.source("ticks", new EventBlock<Integer>());
      core.start();
      IOException refused = assertThrows(IOException.class,
          () -> RecordingMcap.stream(core.recording(), file, McapWriterOptions.defaults()).close());
      assertTrue(refused.getMessage().contains(file.toString()), refused.getMessage());
      assertEquals(List.of(file), writer.files());
    }
    assertFalse(Files.exists(RecordingLock.lockPath(file)));
  }

  /**
   * A merge writes its output at the end by moving it into place: into the path of a writer still
   * writing, that would replace the writer's file (which goes on writing into the file removed).
   * It is refused as a second writer is, and the writer's file stays.
   */
  @Test
  void aMergeIntoThePathOfAWriterStillWritingIsRefused() throws IOException {
    Path input = dir.resolve("input.mcap");
    try (McapWriter writer = McapWriter.open(input, McapWriterOptions.defaults().synchronous())) {
      writer.channel("readings", Reading.class).write(1, 1, 0, new Reading(7));
    }
    Path file = dir.resolve("live.mcap");
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().synchronous().chunkSize(1))) {
      McapChannel<Reading> readings = writer.channel("readings", Reading.class);
      assertTrue(readings.write(1, 1, 0, new Reading(1)));

      IOException refused = assertThrows(IOException.class, () -> McapMerge.merge(List.of(input), file));

      assertTrue(refused.getMessage().contains(file.toString())
          && refused.getMessage().contains("pid " + ProcessHandle.current().pid()), refused.getMessage());
      assertTrue(readings.write(2, 2, 1, new Reading(2)));
    }
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(List.of(1, 2), reader.messages("readings", Reading.class).map(m -> m.value().value()).toList(),
          "the writer's file, not the merge's");
    }
    assertFalse(Files.exists(RecordingLock.lockPath(file)));
  }

  /**
   * A device is no recording that a second writer could truncate: writers to /dev/null (as
   * prime-bench's McapWriterBenchmark opens two) are not held, and make no lock file in /dev.
   */
  @Test
  void writersToADeviceAreNotHeld() throws IOException {
    Path devNull = Path.of("/dev/null");
    assumeTrue(Files.exists(devNull) && !Files.isRegularFile(devNull), "needs /dev/null");
    try (McapWriter first = McapWriter.open(devNull, McapWriterOptions.defaults().synchronous());
        McapWriter second = McapWriter.open(devNull)) {
      assertTrue(first.channel("readings", Reading.class).write(1, 1, 0, new Reading(1)));
      assertTrue(second.channel("readings", Reading.class).write(1, 1, 0, new Reading(1)));
      assertFalse(Files.exists(RecordingLock.lockPath(devNull)), "no lock file beside a device");
    }
  }

  @Test
  void aWriterInAnotherProcessIsRefusedNamingItsPidUntilThatProcessDies() throws Exception {
    Path file = dir.resolve("shared.mcap");
    String java = new File(System.getProperty("java.home"), "bin/java").getPath();
    Process holder = new ProcessBuilder(java, "-cp", System.getProperty("java.class.path"),
        CrashingRecorder.class.getName(), file.toString(), "10", "1")
        .redirectError(ProcessBuilder.Redirect.INHERIT)
        .start();
    try (BufferedReader out = new BufferedReader(new InputStreamReader(holder.getInputStream(), StandardCharsets.UTF_8))) {
      assertEquals("WROTE 10", out.readLine(), "the other process writes");
      long sizeBefore = Files.size(file);

      IOException refused = assertThrows(IOException.class, () -> McapWriter.open(file).close());

      String message = refused.getMessage();
      assertTrue(message.contains(file.toString()), message);
      assertTrue(message.contains("pid " + holder.pid()), "names the other process: " + message);
      assertEquals(sizeBefore, Files.size(file), "its file is not truncated");
    } finally {
      holder.destroyForcibly();
      assertTrue(holder.waitFor(30, TimeUnit.SECONDS), "the holder died");
    }
    try (McapReader reader = McapReader.openUnfinished(file)) {
      assertEquals(10, reader.messageCount("ticks"), "the other process's messages are all there");
    }
    // the lock dies with its process: the lock file it left does not stop a new writer
    try (McapWriter writer = McapWriter.open(file)) {
      assertEquals(List.of(file), writer.files());
    }
    assertFalse(Files.exists(RecordingLock.lockPath(file)));
  }
}

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

  /**
   * A rotating writer truncates each next file as it rotates into it: a second writer (recorder,
   * merge) at one of its rotated files' names would lose its file to it, or truncate the file the
   * first one finished there. Refused, naming both paths and the holder.
   */
  @Test
  void aWriterAtARotatedFileOfARecordingBeingWrittenIsRefused() throws Exception {
    Path file = dir.resolve("run.mcap");
    Path rotated = McapWriter.rotatedPath(file, 1);
    McapWriterOptions options = McapWriterOptions.defaults().synchronous().chunkSize(1).rotateAtSize(1);
    try (PrimeCore core = new LibertyCore(CoreConfig.builder().recording(RecordingOptions.ring(4)).build());
        McapWriter first = McapWriter.open(file, options)) {
      core.source("ticks", new EventBlock<Integer>());
      core.start();
      McapChannel<Reading> readings = first.channel("readings", Reading.class);
      for (int i = 0; i < 3; i++) {
        assertTrue(readings.write(i, i, i, new Reading(i)));
      }
      long sizeBefore = Files.size(rotated);

      IOException refused = assertThrows(IOException.class, () -> McapWriter.open(rotated).close());

      String message = refused.getMessage();
      assertTrue(message.contains(rotated.toString()) && message.contains(file.toString()), message);
      assertTrue(message.contains("pid " + ProcessHandle.current().pid()), "names the holder: " + message);
      assertTrue(message.contains(Thread.currentThread().getName()), "names the holder's thread: " + message);
      assertEquals(sizeBefore, Files.size(rotated), "the first writer's rotated file is not truncated");
      Path later = McapWriter.rotatedPath(file, 4);
      IOException recorder = assertThrows(IOException.class,
          () -> RecordingMcap.stream(core.recording(), later, McapWriterOptions.defaults()).close());
      assertTrue(recorder.getMessage().contains(later.toString()), recorder.getMessage());
      IOException merge = assertThrows(IOException.class, () -> McapMerge.merge(List.of(file), later));
      assertTrue(merge.getMessage().contains(file.toString()), merge.getMessage());
      assertFalse(Files.exists(later), "nothing is written at the name the first writer rotates into");
      for (int i = 3; i < 6; i++) {
        assertTrue(readings.write(i, i, i, new Reading(i)), "the first writer goes on");
      }
    }
    long messages = 0;
    for (Path part : McapReader.recordingFiles(file)) {
      try (McapReader reader = McapReader.open(part)) {
        messages += reader.messageCount("readings");
      }
    }
    assertEquals(6, messages, "every message of the first writer");
    try (McapWriter again = McapWriter.open(rotated)) {
      assertEquals(List.of(rotated), again.files(), "the name is free once the first writer is closed");
    }
    assertFalse(Files.exists(RecordingLock.lockPath(file)) || Files.exists(RecordingLock.lockPath(rotated)));
  }

  /**
   * A writer at {@code run.mcap} deletes {@code run-0001.mcap} as an earlier recording's rotated
   * file, then rotates into it: refused while a writer there is writing, whose file stays.
   */
  @Test
  void aWriterWhoseRotatedFilesWouldOverlapAFileBeingWrittenIsRefused() throws IOException {
    Path file = dir.resolve("take.mcap");
    Path rotated = McapWriter.rotatedPath(file, 1);
    try (McapWriter live = McapWriter.open(rotated, McapWriterOptions.defaults().synchronous().chunkSize(1))) {
      McapChannel<Reading> readings = live.channel("readings", Reading.class);
      assertTrue(readings.write(1, 1, 0, new Reading(1)));
      long sizeBefore = Files.size(rotated);

      IOException refused = assertThrows(IOException.class,
          () -> McapWriter.open(file, McapWriterOptions.defaults().rotateAtSize(1)).close());

      String message = refused.getMessage();
      assertTrue(message.contains(rotated.toString()) && message.contains(file.toString()), message);
      assertTrue(message.contains("pid " + ProcessHandle.current().pid()), "names the holder: " + message);
      assertTrue(Files.exists(rotated), "the file being written is not deleted");
      assertEquals(sizeBefore, Files.size(rotated));
      assertFalse(Files.exists(file), "the refused writer made no file");
      assertTrue(readings.write(2, 2, 1, new Reading(2)), "the writer goes on");
    }
    try (McapReader reader = McapReader.open(rotated)) {
      assertEquals(2, reader.messageCount("readings"));
    }
    assertFalse(Files.exists(RecordingLock.lockPath(rotated)));
  }

  /**
   * A merge into {@code take.mcap} while a writer writes {@code take-0001.mcap} is refused naming
   * that writer: {@link McapReader#recordingFiles} would list the live file as the second file of
   * the merge's recording.
   */
  @Test
  void aMergeIntoTheFirstFileOfARotatedFileBeingWrittenIsRefused() throws IOException {
    Path input = dir.resolve("input.mcap");
    try (McapWriter writer = McapWriter.open(input, McapWriterOptions.defaults().synchronous())) {
      writer.channel("readings", Reading.class).write(1, 1, 0, new Reading(7));
    }
    Path file = dir.resolve("take.mcap");
    Path rotated = McapWriter.rotatedPath(file, 1);
    try (McapWriter live = McapWriter.open(rotated, McapWriterOptions.defaults().synchronous().chunkSize(1))) {
      McapChannel<Reading> readings = live.channel("readings", Reading.class);
      assertTrue(readings.write(1, 1, 0, new Reading(1)));

      IOException refused = assertThrows(IOException.class, () -> McapMerge.merge(List.of(input), file),
          () -> "merged while " + rotated + " is written; the merge's recording is now "
              + McapReader.recordingFiles(file));

      String message = refused.getMessage();
      assertTrue(message.contains(rotated.toString()) && message.contains(file.toString()), message);
      assertTrue(message.contains("pid " + ProcessHandle.current().pid()), "names the holder: " + message);
      assertFalse(Files.exists(file), "the refused merge made no file");
      assertTrue(readings.write(2, 2, 1, new Reading(2)), "the writer goes on");
    }
    assertFalse(Files.exists(RecordingLock.lockPath(file)), "the refused merge leaves no lock file");
    McapMerge.merge(List.of(input), dir.resolve("elsewhere.mcap"));
  }

  /**
   * The look at an overlapping path's lock file needs no right to write it: a lock file that
   * cannot be opened to write (here a folder, which no writer can hold; for a user other than
   * root, also another user's lock file) does not fail the open of a writer that finds no holder.
   */
  @Test
  void aLockFileOfAnOverlappingPathThatCannotBeWrittenDoesNotFailTheLook() throws IOException {
    Path file = dir.resolve("take.mcap");
    Files.createDirectory(RecordingLock.lockPath(McapWriter.rotatedPath(file, 1)));

    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().synchronous())) {
      assertTrue(writer.channel("readings", Reading.class).write(1, 1, 0, new Reading(1)));
    }

    try (McapReader reader = McapReader.open(file)) {
      assertEquals(1, reader.messageCount("readings"));
    }
  }

  /**
   * A writer whose own lock file cannot be opened to write (a folder with its name; for a user
   * other than root, also another user's lock file) is refused saying which file and what to do.
   */
  @Test
  void aLockFileThatCannotBeOpenedRefusesTheWriterSayingWhatToDo() throws IOException {
    Path file = dir.resolve("take.mcap");
    Path lockFile = Files.createDirectory(RecordingLock.lockPath(file));

    IOException refused = assertThrows(IOException.class, () -> McapWriter.open(file).close());

    String message = refused.getMessage();
    assertTrue(message.contains("cannot open an MCAP writer at " + file) && message.contains("lock file " + lockFile),
        message);
    assertTrue(message.contains("delete " + lockFile), "says how to fix it: " + message);
    assertFalse(Files.exists(file), "the refused writer made no file");
  }

  /**
   * Another process writes {@code b-0001.mcap}, and its lock file is not writable to this user:
   * a writer at {@code b.mcap} is still refused naming that process, not failed by the look.
   * (Root writes any file: the test needs another user.)
   */
  @Test
  void anotherProcesssLockFileThatCannotBeWrittenStillNamesItsHolder() throws Exception {
    Path b = dir.resolve("b.mcap");
    Path bRotated = McapWriter.rotatedPath(b, 1);
    Process holder = startHolder(bRotated);
    try {
      try (BufferedReader out = new BufferedReader(new InputStreamReader(holder.getInputStream(), StandardCharsets.UTF_8))) {
        assertEquals("WROTE 3", out.readLine(), "the other process writes");
      }
      Path lockFile = RecordingLock.lockPath(bRotated);
      assertTrue(lockFile.toFile().setWritable(false, false));
      assumeTrue(!Files.isWritable(lockFile), "this user (root) writes a file whatever its mode");

      IOException refused = assertThrows(IOException.class, () -> McapWriter.open(b).close());

      assertTrue(refused.getMessage().contains(bRotated.toString())
          && refused.getMessage().contains("pid " + holder.pid()), refused.getMessage());

      // one it cannot even read: it cannot tell, and says which file stops it and what to do
      assertTrue(lockFile.toFile().setReadable(false, false));
      IOException unread = assertThrows(IOException.class, () -> McapWriter.open(b).close());
      assertTrue(unread.getMessage().contains("lock file " + lockFile) && unread.getMessage().contains("delete "
          + lockFile), unread.getMessage());
      assertFalse(Files.exists(b), "the refused writer made no file");
    } finally {
      holder.destroyForcibly();
      assertTrue(holder.waitFor(30, TimeUnit.SECONDS), "the holder died");
    }
  }

  /**
   * A symbolic link to a file being written names that file: a writer opened at the link is
   * refused as one opened at the file itself, and leaves the file as it was.
   */
  @Test
  void aWriterAtASymbolicLinkToAFileBeingWrittenIsRefused() throws IOException {
    Path file = dir.resolve("run.mcap");
    Path link = dir.resolve("latest.mcap");
    McapWriterOptions options = McapWriterOptions.defaults().synchronous().chunkSize(1);
    try (McapWriter writer = McapWriter.open(file, options)) {
      McapChannel<Reading> readings = writer.channel("readings", Reading.class);
      assertTrue(readings.write(1, 1, 0, new Reading(1)));
      try {
        Files.createSymbolicLink(link, file.getFileName());
      } catch (UnsupportedOperationException | IOException e) {
        assumeTrue(false, "no symbolic links here: " + e);
      }
      long sizeBefore = Files.size(file);

      IOException refused = assertThrows(IOException.class, () -> McapWriter.open(link, options).close(),
          () -> "opened at " + link + " while " + file + " is written; its size is now " + sizeOf(file));

      String message = refused.getMessage();
      assertTrue(message.contains(link.toString()) && message.contains(file.getFileName().toString()), message);
      assertTrue(message.contains("pid " + ProcessHandle.current().pid()), "names the holder: " + message);
      assertEquals(sizeBefore, Files.size(file), "the file being written is not truncated");
      assertTrue(readings.write(2, 2, 1, new Reading(2)), "the writer goes on");
    }
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(2, reader.messageCount("readings"));
    }
    assertFalse(Files.exists(RecordingLock.lockPath(file)));
    assertFalse(Files.exists(RecordingLock.lockPath(link)), "the refused writer leaves no lock file");
    try (McapWriter atLink = McapWriter.open(link, options)) {
      assertEquals(List.of(link), atLink.files(), "a writer opens at the link once the file is free");
      IOException atFile = assertThrows(IOException.class, () -> McapWriter.open(file, options).close());
      assertTrue(atFile.getMessage().contains(file.toString()), atFile.getMessage());
    }
    assertFalse(Files.exists(RecordingLock.lockPath(file)), "the writer at the link gave the file up");
  }

  private static String sizeOf(Path file) {
    try {
      return Long.toString(Files.size(file));
    } catch (IOException e) {
      return e.toString();
    }
  }

  /** Two rotated names of one recording overlap with it, not with each other: both are written at once. */
  @Test
  void writersAtTwoRotatedNamesOfOneRecordingWriteAtOnce() throws IOException {
    Path file = dir.resolve("take.mcap");
    McapWriterOptions options = McapWriterOptions.defaults().synchronous();
    try (McapWriter one = McapWriter.open(McapWriter.rotatedPath(file, 1), options);
        McapWriter two = McapWriter.open(McapWriter.rotatedPath(file, 2), options)) {
      assertTrue(one.channel("readings", Reading.class).write(1, 1, 0, new Reading(1)));
      assertTrue(two.channel("readings", Reading.class).write(1, 1, 0, new Reading(2)));
    }
    for (int index = 1; index <= 2; index++) {
      try (McapReader reader = McapReader.open(McapWriter.rotatedPath(file, index))) {
        assertEquals(1, reader.messageCount("readings"));
      }
    }
  }

  /**
   * Overlapping recordings across processes: another process writes {@code a.mcap} and {@code
   * b-0001.mcap}; here, {@code a-0001.mcap} (a rotated file of its recording) and {@code b.mcap}
   * (whose writer would delete its file) are refused naming its pid, until it dies.
   */
  @Test
  void aWriterWhoseFilesOverlapAnotherProcesssRecordingIsRefusedUntilThatProcessDies() throws Exception {
    Path a = dir.resolve("a.mcap");
    Path b = dir.resolve("b.mcap");
    Path bRotated = McapWriter.rotatedPath(b, 1);
    Process holderOfA = startHolder(a);
    Process holderOfB = startHolder(bRotated);
    try {
      for (Process holder : List.of(holderOfA, holderOfB)) {
        try (BufferedReader out = new BufferedReader(new InputStreamReader(holder.getInputStream(), StandardCharsets.UTF_8))) {
          assertEquals("WROTE 3", out.readLine(), "the other process writes");
        }
      }
      long sizeOfB = Files.size(bRotated);
      Path aRotated = McapWriter.rotatedPath(a, 1);

      IOException intoA = assertThrows(IOException.class, () -> McapWriter.open(aRotated).close());
      IOException overB = assertThrows(IOException.class, () -> McapWriter.open(b).close());

      assertTrue(intoA.getMessage().contains(aRotated.toString()) && intoA.getMessage().contains(a.toString())
          && intoA.getMessage().contains("pid " + holderOfA.pid()), intoA.getMessage());
      assertTrue(overB.getMessage().contains(b.toString()) && overB.getMessage().contains(bRotated.toString())
          && overB.getMessage().contains("pid " + holderOfB.pid()), overB.getMessage());
      assertFalse(Files.exists(aRotated), "nothing written at a name of the other process's recording");
      assertEquals(sizeOfB, Files.size(bRotated), "the other process's file is not deleted nor truncated");
    } finally {
      for (Process holder : List.of(holderOfA, holderOfB)) {
        holder.destroyForcibly();
        assertTrue(holder.waitFor(30, TimeUnit.SECONDS), "the holder died");
      }
    }
    // the locks die with their process
    try (McapWriter intoA = McapWriter.open(McapWriter.rotatedPath(a, 1));
        McapWriter overB = McapWriter.open(b)) {
      assertEquals(List.of(McapWriter.rotatedPath(a, 1)), intoA.files());
      assertEquals(List.of(b), overB.files());
    }
  }

  private static Process startHolder(Path file) throws IOException {
    String java = new File(System.getProperty("java.home"), "bin/java").getPath();
    return new ProcessBuilder(java, "-cp", System.getProperty("java.class.path"),
        CrashingRecorder.class.getName(), file.toString(), "3", "1")
        .redirectError(ProcessBuilder.Redirect.INHERIT)
        .start();
  }
}

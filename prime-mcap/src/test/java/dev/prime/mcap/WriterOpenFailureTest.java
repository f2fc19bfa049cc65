package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;
import static org.junit.jupiter.api.Assumptions.assumeTrue;

import java.io.IOException;
import java.nio.ByteBuffer;
import java.nio.channels.FileChannel;
import java.nio.file.Files;
import java.nio.file.LinkOption;
import java.nio.file.Path;
import java.util.Arrays;
import java.util.List;
import java.util.stream.Stream;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * {@link McapWriter#open} deletes the rotated files of an earlier recording at its path; when one
 * cannot be deleted, the open fails saying which and why, and leaves no file open behind it.
 */
class WriterOpenFailureTest {
  @TempDir Path dir;

  /** The descriptors of this JVM open on {@code file} (Linux: /proc/self/fd). */
  private static List<Path> openDescriptorsOn(Path file) throws IOException {
    Path target = file.toAbsolutePath().normalize();
    try (Stream<Path> fds = Files.list(Path.of("/proc/self/fd"))) {
      return fds.filter(fd -> {
        try {
          return Files.readSymbolicLink(fd).equals(target);
        } catch (IOException | UnsupportedOperationException e) {
          return false; // closed meanwhile, or not a link
        }
      }).toList();
    }
  }

  @Test
  void anEarlierRotatedFileThatCannotBeDeletedFailsTheOpenWithNothingLeftOpen() throws Exception {
    assumeTrue(Files.isDirectory(Path.of("/proc/self/fd")), "needs /proc/self/fd to see open files");
    Path file = dir.resolve("run.mcap");
    Path blocking = Files.createDirectory(McapWriter.rotatedPath(file, 1));
    Files.writeString(blocking.resolve("notes.txt"), "a folder with the name of a rotated file");

    IOException e = assertThrows(IOException.class, () -> McapWriter.open(file).close());

    assertEquals(List.of(), openDescriptorsOn(file), "the first file's output is closed");
    assertTrue(e.getMessage().contains(blocking.toString()), e.getMessage());
    assertTrue(e.getMessage().contains("earlier recording"), e.getMessage());
  }

  record Reading(int value) {}

  /**
   * An earlier recording at the path whose last rotated file cannot be deleted (a folder with its
   * name: a failure root cannot bypass either) is left as it was, its first file included: a
   * refused open does not leave a first file of its own beside the earlier recording's rotated
   * files.
   */
  @Test
  void anEarlierRecordingWithARotatedFileThatCannotBeDeletedIsLeftWhole() throws Exception {
    Path file = dir.resolve("run.mcap");
    try (McapWriter earlier = McapWriter.open(file, McapWriterOptions.defaults().synchronous().chunkSize(1)
        .rotateAtSize(1))) {
      McapChannel<Reading> readings = earlier.channel("readings", Reading.class);
      for (int i = 0; i < 2; i++) {
        assertTrue(readings.write(i, i, i, new Reading(i)));
      }
    }
    Path second = McapWriter.rotatedPath(file, 1);
    assertTrue(Files.isRegularFile(second), "the earlier recording was rotated");
    byte[] firstBefore = Files.readAllBytes(file);
    byte[] secondBefore = Files.readAllBytes(second);
    Path blocking = Files.createDirectory(McapWriter.rotatedPath(file, 2));
    Files.writeString(blocking.resolve("notes.txt"), "a folder with the name of a rotated file");

    IOException e = assertThrows(IOException.class, () -> McapWriter.open(file).close());

    assertTrue(e.getMessage().contains(blocking.toString()), e.getMessage());
    assertTrue(Arrays.equals(firstBefore, Files.readAllBytes(file)),
        "the earlier recording's first file is not overwritten: " + e.getMessage());
    assertTrue(Arrays.equals(secondBefore, Files.readAllBytes(second)),
        "nor its rotated file deleted: " + e.getMessage());
    assertFalse(Files.exists(RecordingLock.lockPath(file)), "the path is given up");
  }

  /**
   * A first file that cannot be opened to write (here a folder at its path) fails the open
   * before the rotated files of an earlier recording there are deleted: they stay.
   */
  @Test
  void aFirstFileThatCannotBeWrittenFailsTheOpenBeforeAnythingIsDeleted() throws Exception {
    Path file = Files.createDirectory(dir.resolve("run.mcap"));
    Path rotated = McapWriter.rotatedPath(file, 1);
    Files.writeString(rotated, "an earlier recording's rotated file");

    IOException e = assertThrows(IOException.class, () -> McapWriter.open(file).close());

    assertTrue(Files.exists(rotated), "the earlier rotated file is not deleted for an open that fails: " + e);
    assertFalse(Files.exists(RecordingLock.lockPath(file)), "the path is given up");
  }

  /**
   * A null library name is bad input: it is refused where it is given, naming the option, so no
   * writer opens with it and the recording at the path stays as it was.
   */
  @Test
  void aNullLibraryNameIsRefusedWhereItIsGivenAndTheRecordingAtThePathStays() throws IOException {
    Path file = dir.resolve("run.mcap");
    try (McapWriter earlier = McapWriter.open(file, McapWriterOptions.defaults().synchronous())) {
      assertTrue(earlier.channel("ticks", Integer.class).write(1, 1, 1, 7));
    }
    NullPointerException refused =
        assertThrows(NullPointerException.class,
            () -> McapWriter.open(file, McapWriterOptions.defaults().library(null)).close());
    assertTrue(String.valueOf(refused.getMessage()).contains("library"), String.valueOf(refused.getMessage()));
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(1, reader.messageCount("ticks"), "the recording at the path stays");
    }
  }

  /**
   * A library name MCAP's UTF-8 strings cannot hold (an unpaired surrogate) is refused where it is
   * given, as a topic or a Metadata name is, rather than written into every Header as {@code ?}.
   */
  @Test
  void aLibraryNameThatIsNotUnicodeTextIsRefusedWhereItIsGiven() {
    IllegalArgumentException refused =
        assertThrows(IllegalArgumentException.class,
            () -> McapWriterOptions.defaults().library("robot\uD800"));
    assertTrue(refused.getMessage().contains("library") && refused.getMessage().contains("unpaired surrogate"),
        refused.getMessage());
  }

  /** Opens files for real, and hands out channels whose writes fail as a full disk's do. */
  private static final OutputOpener FULL_DISK = path -> new ForwardingFileChannel(OutputOpener.FILES.open(path)) {
    @Override
    public int write(ByteBuffer source) throws IOException {
      throw new IOException("No space left on device");
    }
  };

  /**
   * A failure writing the magic and Header (after the file was truncated: no check before it can
   * foresee an I/O error) fails the open saying which file and what became of it: an earlier
   * file there is left empty, as the open's documentation says, and the path is given up.
   */
  @Test
  void aFailureWritingTheHeaderSaysTheEarlierFileWasEmptied() throws Exception {
    assumeTrue(Files.isDirectory(Path.of("/proc/self/fd")), "needs /proc/self/fd to see open files");
    Path file = dir.resolve("run.mcap");
    try (McapWriter earlier = McapWriter.open(file, McapWriterOptions.defaults().synchronous())) {
      assertTrue(earlier.channel("ticks", Integer.class).write(1, 1, 1, 7));
    }

    IOException e = assertThrows(IOException.class,
        () -> McapWriter.open(file, McapWriterOptions.defaults().synchronous(), FULL_DISK).close());

    assertTrue(e.getMessage().contains(file.toString()) && e.getMessage().contains("No space left on device")
        && e.getMessage().contains("truncated"), e.getMessage());
    assertEquals(0, Files.size(file), "the earlier file is left empty, as documented: " + e.getMessage());
    assertEquals(List.of(), openDescriptorsOn(file), "the file's output is closed");
    assertFalse(Files.exists(RecordingLock.lockPath(file)), "the path is given up");
  }

  /** A failure writing the Header of a file the open created removes that file: the path is as it was. */
  @Test
  void aFailureWritingTheHeaderOfANewFileLeavesNoFile() {
    Path file = dir.resolve("new.mcap");

    IOException e = assertThrows(IOException.class,
        () -> McapWriter.open(file, McapWriterOptions.defaults(), FULL_DISK).close());

    assertTrue(e.getMessage().contains(file.toString()), e.getMessage());
    assertFalse(Files.exists(file), "the file the open created is removed: " + e.getMessage());
    assertFalse(Files.exists(RecordingLock.lockPath(file)), "the path is given up");
  }

  /**
   * A symbolic link whose file is not there yet: the open creates that file, so a failure writing
   * its Header removes it (the link is left as it was, leading nowhere) and says so, not that an
   * earlier file's contents are gone.
   */
  @Test
  void aFailureWritingTheHeaderOfTheFileADanglingLinkLeadsToRemovesThatFile() throws Exception {
    Path target = dir.resolve("run.mcap");
    Path link = dir.resolve("latest.mcap");
    try {
      Files.createSymbolicLink(link, target.getFileName());
    } catch (UnsupportedOperationException | IOException e) {
      assumeTrue(false, "no symbolic links here: " + e);
    }

    IOException e = assertThrows(IOException.class,
        () -> McapWriter.open(link, McapWriterOptions.defaults().synchronous(), FULL_DISK).close());

    assertFalse(Files.exists(target, LinkOption.NOFOLLOW_LINKS), "the file the open created is removed: " + e.getMessage());
    assertTrue(Files.isSymbolicLink(link), "the link stays: " + e.getMessage());
    assertTrue(e.getMessage().contains("removed") && !e.getMessage().contains("what it held before is gone"),
        e.getMessage());
    assertFalse(Files.exists(RecordingLock.lockPath(link)) || Files.exists(RecordingLock.lockPath(target)),
        "the path is given up");
  }

  /**
   * An Error while the Header is written (the heap exhausted) still gives the path up, with the
   * file's output closed: the next writer there is not refused as if this one held it.
   */
  @Test
  void anErrorWritingTheHeaderGivesThePathUp() throws Exception {
    Path file = dir.resolve("run.mcap");
    OutputOpener exhausted = path -> new ForwardingFileChannel(OutputOpener.FILES.open(path)) {
      @Override
      public int write(ByteBuffer source) {
        throw new OutOfMemoryError("a heap exhausted while the Header is written");
      }
    };

    assertThrows(OutOfMemoryError.class,
        () -> McapWriter.open(file, McapWriterOptions.defaults().synchronous(), exhausted).close());

    assertFalse(Files.exists(RecordingLock.lockPath(file)), "the path is given up");
    try (McapWriter next = McapWriter.open(file, McapWriterOptions.defaults().synchronous())) {
      assertTrue(next.channel("ticks", Integer.class).write(1, 1, 1, 7));
    }
  }
}

package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;
import static org.junit.jupiter.api.Assumptions.assumeTrue;

import java.io.IOException;
import java.nio.file.FileSystems;
import java.nio.file.Files;
import java.nio.file.Path;
import java.nio.file.attribute.PosixFilePermission;
import java.nio.file.attribute.PosixFilePermissions;
import java.util.ArrayList;
import java.util.List;
import java.util.Set;
import java.util.stream.Stream;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * A merge into a path that is a symbolic link writes the file the link leads to, as a writer
 * opened there does: the link stays a link to that file, and the file holds the merge.
 */
class MergeOutputLinkTest {
  @TempDir Path dir;

  record Reading(int value) {}

  private Path recording(Path file, String topic, int count) throws IOException {
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().synchronous())) {
      McapChannel<Reading> channel = writer.channel(topic, Reading.class);
      for (int i = 0; i < count; i++) {
        assertTrue(channel.write(i, i, i, new Reading(i)));
      }
    }
    return file;
  }

  private static Path link(Path link, Path target) {
    try {
      return Files.createSymbolicLink(link, target);
    } catch (UnsupportedOperationException | IOException e) {
      assumeTrue(false, "no symbolic links here: " + e);
      throw new AssertionError(e);
    }
  }

  private static List<Path> filesIn(Path folder) throws IOException {
    try (Stream<Path> files = Files.list(folder)) {
      return files.sorted().toList();
    }
  }

  @Test
  void aMergeIntoASymbolicLinkWritesTheFileItLinksToAndKeepsTheLink() throws Exception {
    Path inputs = Files.createDirectory(dir.resolve("inputs"));
    Path runs = Files.createDirectory(dir.resolve("runs"));
    Path robot = recording(inputs.resolve("robot.mcap"), "robot", 3);
    Path worker = recording(inputs.resolve("worker.mcap"), "worker", 2);
    Path target = recording(runs.resolve("run.mcap"), "earlier", 1);
    Path link = link(dir.resolve("latest.mcap"), dir.relativize(target));

    McapMerge.Result result = McapMerge.merge(List.of(robot, worker), link);

    assertEquals(5, result.messages());
    assertTrue(Files.isSymbolicLink(link), "the output path is still a symbolic link");
    assertEquals(dir.relativize(target), Files.readSymbolicLink(link), "to the same file");
    try (McapReader reader = McapReader.open(target)) {
      assertEquals(List.of("robot", "worker"), reader.channels().stream().map(ChannelInfo::topic).toList(),
          "the file the link leads to holds the merge");
    }
    assertEquals(List.of(inputs, link, runs), filesIn(dir), "nothing left beside the link");
    assertEquals(List.of(target), filesIn(runs), "nor beside the file");

    // a link whose file is not there yet: the merge makes it, where the link leads
    Path fresh = runs.resolve("fresh.mcap");
    Path dangling = link(dir.resolve("next.mcap"), fresh);
    McapMerge.merge(List.of(robot), dangling);
    assertTrue(Files.isSymbolicLink(dangling), "the link stays a link");
    try (McapReader reader = McapReader.open(fresh)) {
      assertEquals(3, reader.messageCount("robot"));
    }
  }

  /** A recording of at least {@code files} files at {@code first}, all but the first rotated. */
  private static List<Path> rotatedRecording(Path first, int files) throws IOException {
    McapWriterOptions options = McapWriterOptions.defaults().synchronous().chunkSize(64).rotateAtSize(512);
    try (McapWriter writer = McapWriter.open(first, options)) {
      McapChannel<Reading> channel = writer.channel("earlier", Reading.class);
      for (int i = 0; i < 1_000 && writer.files().size() < files; i++) {
        assertTrue(channel.write(i, i, i, new Reading(i)));
      }
      assertTrue(writer.files().size() >= files, "the recording rotated: " + writer.files());
      return writer.files();
    }
  }

  /** {@code files} with the first replaced by {@code first}: the recording read through another name. */
  private static List<Path> readThrough(Path first, List<Path> files) {
    List<Path> through = new ArrayList<>(files);
    through.set(0, first);
    return through;
  }

  /**
   * A writer opened at a link ({@code latest.mcap} to {@code runs/run.mcap}) rotates into files
   * named after the file the link leads to, beside it ({@code runs/run-0001.mcap}), and it, like a
   * merge into the link, replaces the recording there, deleting that recording's rotated files:
   * read through either name, the recording is the new one, with nothing of the earlier one. A
   * file named after the link is no file of that recording, and is left; and a link moved on to
   * the next run leaves the earlier run whole.
   */
  @Test
  void aWriterAtALinkAndAMergeIntoOneReplaceTheRecordingOfTheFileItLeadsTo() throws Exception {
    Path robot = recording(dir.resolve("robot.mcap"), "robot", 3);
    Path runs = Files.createDirectory(dir.resolve("runs"));
    Path target = runs.resolve("run.mcap");
    List<Path> earlier = rotatedRecording(target, 5);
    Path link = link(dir.resolve("latest.mcap"), dir.relativize(target));
    Path namedAfterLink = Files.writeString(McapWriter.rotatedPath(link, 1), "a file named after the link");

    List<Path> written = rotatedRecording(link, 3);
    assertTrue(written.size() < earlier.size(), written + " " + earlier);
    assertEquals(link, written.get(0), "the first file as the writer was given it");
    assertEquals(McapWriter.rotatedPath(target, 1), written.get(1),
        "rotated files are named after the file the link leads to, beside it");
    assertEquals(written, McapReader.recordingFiles(link), "read through the link: the new recording alone");
    assertEquals(readThrough(target, written), McapReader.recordingFiles(target),
        "read through the file: the same recording, nothing of the earlier one");
    try (McapReader reader = McapReader.open(written.get(written.size() - 1))) {
      assertEquals(List.of("earlier"), reader.channels().stream().map(ChannelInfo::topic).toList());
    }
    assertTrue(Files.exists(namedAfterLink), "a file named after the link is not the recording's");

    IllegalArgumentException own =
        assertThrows(IllegalArgumentException.class, () -> McapMerge.merge(List.of(written.get(1)), link));
    assertTrue(own.getMessage().contains("is rotated file 1 of a recording at " + link), own.getMessage());
    McapMerge.merge(List.of(robot), link);
    assertEquals(List.of(link), McapReader.recordingFiles(link), "the merge is the recording at the link");
    assertEquals(List.of(target), McapReader.recordingFiles(target), "and at the file it leads to");
    assertTrue(Files.isSymbolicLink(link), "the link stays");
    assertTrue(Files.exists(namedAfterLink), "and the merge leaves that file too");

    // the link moved on to the next run: the run it led to is left whole
    List<Path> first = rotatedRecording(link, 3);
    Path next = runs.resolve("next.mcap");
    Files.delete(link);
    link(link, dir.relativize(next));
    List<Path> second = rotatedRecording(link, 3);
    assertEquals(readThrough(target, first), McapReader.recordingFiles(target), "the earlier run is kept whole");
    assertEquals(readThrough(next, second), McapReader.recordingFiles(next));
    assertEquals(second, McapReader.recordingFiles(link));
  }

  /**
   * A merge moves a new file onto the output (so that one that fails leaves the output as it
   * was): a hard link to the earlier output keeps the earlier contents, and the output has a new
   * file's permissions, not the earlier file's; a writer, which truncates the file in place, keeps
   * both.
   */
  @Test
  void aMergedOutputIsANewFileHardLinksKeepTheEarlierOneAndPermissionsAreANewFiles() throws Exception {
    assumeTrue(FileSystems.getDefault().supportedFileAttributeViews().contains("posix"), "needs POSIX permissions");
    Path robot = recording(dir.resolve("robot.mcap"), "robot", 3);
    Path output = recording(dir.resolve("run.mcap"), "earlier", 1);
    Path newFile = Files.createFile(dir.resolve("new-file"));
    Set<PosixFilePermission> fresh = Files.getPosixFilePermissions(newFile);
    Set<PosixFilePermission> ownerOnly = PosixFilePermissions.fromString("r--------");
    assumeTrue(!fresh.equals(ownerOnly), "a umask that gives new files r-------- already");
    Files.setPosixFilePermissions(output, ownerOnly);
    Path hard;
    try {
      hard = Files.createLink(dir.resolve("hard.mcap"), output);
    } catch (UnsupportedOperationException | IOException e) {
      assumeTrue(false, "no hard links here: " + e);
      throw new AssertionError(e);
    }
    byte[] earlier = Files.readAllBytes(output);

    McapMerge.merge(List.of(robot), output);

    assertArrayEquals(earlier, Files.readAllBytes(hard), "the hard link keeps the earlier output");
    assertTrue(!Files.isSameFile(hard, output), "and is no longer the output");
    assertEquals(fresh, Files.getPosixFilePermissions(output), "the output has a new file's permissions");
    try (McapReader reader = McapReader.open(output)) {
      assertEquals(3, reader.messageCount("robot"));
    }

    Files.setPosixFilePermissions(output, PosixFilePermissions.fromString("rw-------"));
    Path writerHard = Files.createLink(dir.resolve("writer-hard.mcap"), output);
    try (McapWriter writer = McapWriter.open(output, McapWriterOptions.defaults().synchronous())) {
      assertTrue(writer.channel("later", Reading.class).write(1, 1, 1, new Reading(1)));
    }
    assertTrue(Files.isSameFile(writerHard, output), "a writer rewrites the file in place");
    assertEquals(PosixFilePermissions.fromString("rw-------"), Files.getPosixFilePermissions(output));
  }

  /**
   * A merge into a link holds the file it links to as well: refused, naming the holder, while a
   * writer writes that file, which is left as it was.
   */
  @Test
  void aMergeIntoALinkToAFileBeingWrittenIsRefused() throws Exception {
    Path robot = recording(dir.resolve("robot.mcap"), "robot", 3);
    Path file = dir.resolve("run.mcap");
    Path link = link(dir.resolve("latest.mcap"), file.getFileName());
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().synchronous().chunkSize(1))) {
      McapChannel<Reading> readings = writer.channel("readings", Reading.class);
      assertTrue(readings.write(1, 1, 0, new Reading(1)));
      byte[] before = Files.readAllBytes(file);

      IOException refused = assertThrows(IOException.class, () -> McapMerge.merge(List.of(robot), link));

      assertTrue(refused.getMessage().contains("pid " + ProcessHandle.current().pid()),
          "names the holder: " + refused.getMessage());
      assertArrayEquals(before, Files.readAllBytes(file), "the file being written is left as it was");
      assertTrue(Files.isSymbolicLink(link), "and the link");
      assertTrue(readings.write(2, 2, 1, new Reading(2)), "the writer goes on");
    }
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(2, reader.messageCount("readings"));
    }
  }

  /**
   * A writer at a symbolic link ({@code latest.mcap} to {@code runs/run.mcap}) rotates into
   * {@code runs/run-0001.mcap}..., so a writer at {@code latest-0001.mcap}, beside the link, shares
   * no file with it: neither refuses the other, whichever opens first. A writer at the file it
   * rotates into is still refused.
   */
  @Test
  void aWriterAtALinkAndOneAtAFileNamedAfterTheLinkDoNotOverlap() throws Exception {
    Path runs = Files.createDirectory(dir.resolve("runs"));
    Path target = runs.resolve("run.mcap");
    Path link = link(dir.resolve("latest.mcap"), dir.relativize(target));
    Path besideLink = McapWriter.rotatedPath(link, 1);
    McapWriterOptions options = McapWriterOptions.defaults().synchronous();
    try (McapWriter atLink = McapWriter.open(link, options);
        McapWriter beside = McapWriter.open(besideLink, options)) {
      assertTrue(atLink.channel("robot", Reading.class).write(1, 1, 1, new Reading(1)));
      assertTrue(beside.channel("notes", Reading.class).write(1, 1, 1, new Reading(2)));
      IOException refused = assertThrows(IOException.class,
          () -> McapWriter.open(McapWriter.rotatedPath(target, 1), options).close());
      assertTrue(refused.getMessage().contains(McapWriter.rotatedPath(target, 1).toString()), refused.getMessage());
    }
    try (McapWriter beside = McapWriter.open(besideLink, options);
        McapWriter atLink = McapWriter.open(link, options)) {
      assertTrue(beside.channel("notes", Reading.class).write(1, 1, 1, new Reading(3)));
      assertTrue(atLink.channel("robot", Reading.class).write(1, 1, 1, new Reading(4)));
    }
    try (McapReader reader = McapReader.open(besideLink)) {
      assertEquals(List.of(3), reader.messages("notes", Reading.class).map(m -> m.value().value()).toList());
    }
    assertEquals(List.of(link), McapReader.recordingFiles(link));
  }
}

package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;
import static org.junit.jupiter.api.Assumptions.assumeTrue;

import java.io.IOException;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.List;
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
}

package dev.prime.mcap;

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
}

package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;
import static org.junit.jupiter.api.Assumptions.assumeTrue;

import java.io.IOException;
import java.io.UncheckedIOException;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.List;
import java.util.stream.Stream;
import org.junit.jupiter.api.BeforeEach;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * A recording's path that is a loop of symbolic links names no file: a writer opened there, a
 * merge into it and the lock they take are refused alike, naming the path and the fix, before
 * anything is made or deleted.
 */
class LinkLoopTest {
  @TempDir Path dir;

  private Path loop;
  private Path other;
  private Path input;

  record Reading(int value) {}

  @BeforeEach
  void loopOfLinks() throws IOException {
    input = dir.resolve("robot.mcap");
    try (McapWriter writer = McapWriter.open(input, McapWriterOptions.defaults().synchronous())) {
      assertTrue(writer.channel("robot", Reading.class).write(1, 1, 1, new Reading(1)));
    }
    loop = dir.resolve("latest.mcap");
    other = dir.resolve("other.mcap");
    try {
      Files.createSymbolicLink(loop, other.getFileName());
      Files.createSymbolicLink(other, loop.getFileName());
    } catch (UnsupportedOperationException | IOException e) {
      assumeTrue(false, "no symbolic links here: " + e);
    }
  }

  private List<Path> filesIn() throws IOException {
    try (Stream<Path> files = Files.list(dir)) {
      return files.sorted().toList();
    }
  }

  private void assertRefused(IOException refused, String action) throws IOException {
    String message = refused.getMessage();
    assertTrue(message.startsWith("cannot " + action + " " + loop + ": it is a symbolic link that leads through more"
        + " than " + SymbolicLinks.MAX_LINKS + " links (a loop of them?)"), message);
    assertTrue(message.contains("make it a link to a file"), message);
    assertEquals(List.of(loop, other, input), filesIn(), "nothing is made beside the links");
    assertTrue(Files.isSymbolicLink(loop) && Files.isSymbolicLink(other), "the links stay");
  }

  @Test
  void aWriterAtALoopOfLinksIsRefused() throws IOException {
    IOException refused = assertThrows(IOException.class,
        () -> McapWriter.open(loop, McapWriterOptions.defaults().synchronous()).close());
    assertRefused(refused, "open an MCAP writer at");
  }

  @Test
  void theLockOfALoopOfLinksIsRefused() throws IOException {
    IOException refused = assertThrows(IOException.class,
        () -> RecordingLock.acquire(loop, "open an MCAP writer at", true).release());
    assertRefused(refused, "open an MCAP writer at");
  }

  @Test
  void aMergeIntoALoopOfLinksIsRefused() throws IOException {
    IOException refused = assertThrows(IOException.class, () -> McapMerge.merge(List.of(input), loop));
    assertRefused(refused, "merge into");
  }

  /**
   * Listing the files of a recording at a loop of links is refused, as a writer there is, naming
   * the path and what to do: for a reader, to give the recording's first file (not "no files", as
   * if no recording were there, nor a writer's "write to another path").
   */
  @Test
  void theFilesOfARecordingAtALoopOfLinksAreRefused() throws IOException {
    UncheckedIOException refused = assertThrows(UncheckedIOException.class, () -> McapReader.recordingFiles(loop));
    assertEquals("cannot list the files of the recording at " + loop + ": it is a symbolic link that leads through"
        + " more than " + SymbolicLinks.MAX_LINKS + " links (a loop of them?), so it names no file; give the path"
        + " of the recording's first file, or make the link lead to it", refused.getMessage());
    assertEquals(refused.getMessage(), refused.getCause().getMessage(), "the IOException within says the same");
    assertEquals(List.of(loop, other, input), filesIn(), "nothing is made beside the links");
  }
}

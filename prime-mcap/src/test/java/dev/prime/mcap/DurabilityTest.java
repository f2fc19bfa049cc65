package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.IOException;
import java.io.UncheckedIOException;
import java.nio.ByteBuffer;
import java.nio.channels.FileChannel;
import java.nio.charset.StandardCharsets;
import java.nio.file.AccessDeniedException;
import java.nio.file.Files;
import java.nio.file.Path;
import java.nio.file.StandardOpenOption;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.Collections;
import java.util.List;
import java.util.concurrent.atomic.AtomicReference;
import java.util.function.Supplier;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * What a writer and a merge force to the storage device, watched through the channels they
 * write and force with: a finished file is forced after its last byte and before it is closed,
 * then its folder (a merge's output: before it is moved into place, and the folder after the
 * move), and a write that finishes no file forces nothing.
 */
class DurabilityTest {
  @TempDir Path dir;

  record Reading(int value) {}

  /** What was done to the channels, in order: "write NAME", "force NAME", "close NAME". */
  private final List<String> events = Collections.synchronizedList(new ArrayList<>());

  /** A real channel that logs its writes, forces and close, with what {@code state} says at a force. */
  private final class Watched extends ForwardingFileChannel {
    private final String name;
    private final Supplier<String> state;

    Watched(String name, FileChannel file, Supplier<String> state) {
      super(file);
      this.name = name;
      this.state = state;
    }

    @Override
    public int write(ByteBuffer source) throws IOException {
      events.add("write " + name);
      return super.write(source);
    }

    @Override
    public void force(boolean metaData) throws IOException {
      events.add("force " + name + state.get());
      super.force(metaData);
    }

    @Override
    protected void implCloseChannel() throws IOException {
      events.add("close " + name);
      super.implCloseChannel();
    }
  }

  private OutputOpener watching(Supplier<String> state) {
    return new OutputOpener() {
      @Override
      public FileChannel open(Path path) throws IOException {
        return new Watched(path.getFileName().toString(), OutputOpener.FILES.open(path), state);
      }

      @Override
      public FileChannel openFolder(Path folder) throws IOException {
        return new Watched("folder", FileChannel.open(folder, StandardOpenOption.READ), state);
      }
    };
  }

  private List<String> forcesAndCloses() {
    synchronized (events) {
      return events.stream().filter(event -> !event.startsWith("write ")).toList();
    }
  }

  @Test
  void closeForcesTheFileAfterItsLastByteThenItsFolderAndNoWriteForces() throws IOException {
    Path file = dir.resolve("run.mcap");
    McapWriterOptions options = McapWriterOptions.defaults().synchronous().chunkSize(1);
    try (McapWriter writer = McapWriter.open(file, options, watching(() -> ""))) {
      McapChannel<Reading> readings = writer.channel("readings", Reading.class);
      for (int i = 0; i < 5; i++) {
        assertTrue(readings.write(i, i, i, new Reading(i)));
      }
      assertTrue(events.contains("write run.mcap"), "each message's chunk is written as it closes: " + events);
      assertEquals(List.of(), forcesAndCloses(), "a write forces nothing (a hot path)");
    }
    assertEquals(List.of("force run.mcap", "close run.mcap", "force folder", "close folder"), forcesAndCloses(),
        "close() forces the finished file, then its folder's entry for it: " + events);
    assertEquals(events.lastIndexOf("write run.mcap") + 1, events.indexOf("force run.mcap"),
        "forced after its last byte: " + events);
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(5, reader.messageCount("readings"));
    }
  }

  @Test
  void everyRotatedFileIsForcedAsItIsFinished() throws IOException {
    Path file = dir.resolve("rotated.mcap");
    McapWriterOptions options = McapWriterOptions.defaults().chunkSize(1).rotateAtSize(1);
    McapWriter writer = McapWriter.open(file, options, watching(() -> ""));
    try {
      McapChannel<Reading> readings = writer.channel("readings", Reading.class);
      for (int i = 0; i < 3; i++) {
        assertTrue(readings.write(i, i, i, new Reading(i)));
      }
    } finally {
      writer.close();
    }
    List<Path> files = writer.files();
    assertEquals(3, files.size(), "one file per message: " + files);
    List<String> expected = new ArrayList<>();
    for (Path part : files) {
      String name = part.getFileName().toString();
      expected.addAll(List.of("force " + name, "close " + name, "force folder", "close folder"));
      assertEquals(events.lastIndexOf("write " + name) + 1, events.indexOf("force " + name),
          name + " is forced after its last byte: " + events);
    }
    assertEquals(expected, forcesAndCloses(), "each file is forced, then its folder, as it is finished");
  }

  /**
   * A folder that cannot be opened to be forced (as the JDK refuses one this user may not read)
   * fails close() with an IOException that says which folder, why it was opened and what to do
   * (the JDK's own says only the folder's path);
   * the file itself is finished, and the path free again.
   */
  @Test
  void aFolderThatCannotBeOpenedFailsCloseSayingWhatToDo() throws IOException {
    Path file = dir.resolve("unreadable.mcap");
    OutputOpener refusingFolders =
        new OutputOpener() {
          @Override
          public FileChannel open(Path path) throws IOException {
            return OutputOpener.FILES.open(path);
          }

          @Override
          public FileChannel openFolder(Path folder) throws IOException {
            throw new AccessDeniedException(folder.toString());
          }
        };
    McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().synchronous(), refusingFolders);
    McapChannel<Reading> readings = writer.channel("readings", Reading.class);
    assertTrue(readings.write(1, 1, 1, new Reading(1)));
    IOException failure = assertThrows(IOException.class, writer::close);
    String message = failure.getMessage();
    assertTrue(message.contains("cannot open the folder " + dir.toAbsolutePath()), message);
    assertTrue(message.contains("unreadable.mcap") && message.contains("power cut"), "says why: " + message);
    assertTrue(message.contains("read access"), "says what to do: " + message);
    Throwable cause = failure;
    while (cause != null && !(cause instanceof AccessDeniedException)) {
      cause = cause.getCause();
    }
    assertInstanceOf(AccessDeniedException.class, cause, "the cause is kept: " + failure);
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(1, reader.messageCount("readings"), "the file itself is finished");
    }
  }

  /**
   * A writer opened at a symbolic link writes the file it links to, made in that file's folder
   * (a link not yet pointing at a file): close() forces that folder, whose entry is new, not the
   * link's, whose entry the writer did not change.
   */
  @Test
  void aWriterAtASymbolicLinkForcesTheFolderOfTheFileItWrites() throws IOException {
    Path real = Files.createDirectory(dir.resolve("real"));
    Path links = Files.createDirectory(dir.resolve("links"));
    Path link = Files.createSymbolicLink(links.resolve("latest.mcap"), real.resolve("run.mcap"));
    List<Path> forcedFolders = Collections.synchronizedList(new ArrayList<>());
    OutputOpener recording =
        new OutputOpener() {
          @Override
          public FileChannel open(Path path) throws IOException {
            return OutputOpener.FILES.open(path);
          }

          @Override
          public FileChannel openFolder(Path folder) throws IOException {
            forcedFolders.add(folder);
            return OutputOpener.FILES.openFolder(folder);
          }
        };
    try (McapWriter writer = McapWriter.open(link, McapWriterOptions.defaults().synchronous(), recording)) {
      assertTrue(writer.channel("readings", Reading.class).write(1, 1, 1, new Reading(1)));
    }
    assertTrue(Files.isRegularFile(real.resolve("run.mcap"), java.nio.file.LinkOption.NOFOLLOW_LINKS),
        "the file was made where the link points");
    assertEquals(List.of(real.toRealPath()), forcedFolders, "the folder of the file written, not the link's");
  }

  @Test
  void aMergeIsForcedBeforeItIsMovedIntoPlaceAndTheFolderAfter() throws IOException {
    Path input = dir.resolve("input.mcap");
    try (McapWriter writer = McapWriter.open(input, McapWriterOptions.defaults().synchronous())) {
      McapChannel<Reading> readings = writer.channel("readings", Reading.class);
      for (int i = 0; i < 3; i++) {
        assertTrue(readings.write(i, i, i, new Reading(i)));
      }
    }
    Path output = dir.resolve("merged.mcap");
    // the file the merge is written to until it is complete: the one file it opens to write
    AtomicReference<Path> partial = new AtomicReference<>();
    byte[] earlier = "an earlier merge".getBytes(StandardCharsets.UTF_8);
    Files.write(output, earlier);
    Supplier<String> state = () -> {
      try {
        return " (" + (Files.exists(partial.get()) ? "partial" : "no partial") + ", "
            + (Arrays.equals(Files.readAllBytes(output), earlier) ? "earlier output" : "new output") + ")";
      } catch (IOException e) {
        throw new UncheckedIOException(e);
      }
    };
    OutputOpener watched = watching(state);
    OutputOpener opener = new OutputOpener() {
      @Override
      public FileChannel open(Path path) throws IOException {
        assertTrue(partial.compareAndSet(null, path), "one file opened to write: " + partial.get() + ", " + path);
        return watched.open(path);
      }

      @Override
      public FileChannel openFolder(Path folder) throws IOException {
        return watched.openFolder(folder);
      }
    };

    McapMerge.merge(List.of(input), output, McapMerge.Options.defaults(), opener);

    String name = partial.get().getFileName().toString();
    assertEquals(dir, partial.get().getParent(), "written beside the output: " + partial.get());
    assertEquals(
        List.of(
            "force " + name + " (partial, earlier output)",
            "close " + name,
            "force folder (no partial, new output)",
            "close folder"),
        forcesAndCloses(),
        "the merge is forced where it is written, before it replaces the earlier one; the folder after: " + events);
    try (McapReader reader = McapReader.open(output)) {
      assertEquals(3, reader.messageCount("readings"));
    }
  }
}

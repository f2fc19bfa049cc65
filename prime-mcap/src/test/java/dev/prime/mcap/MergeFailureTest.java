package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.RandomAccessFile;
import java.nio.ByteBuffer;
import java.nio.ByteOrder;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.List;
import java.util.stream.Stream;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * A merge that fails part way (an input's chunk found corrupt while its messages are read) leaves
 * no half-written output: the output path keeps what it held before (an earlier merge), or stays
 * absent, and no stray file is left beside it.
 */
class MergeFailureTest {
  @TempDir Path dir;

  record Reading(int value) {}

  private Path recording(String name, int count) throws Exception {
    Path file = dir.resolve(name);
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().chunkSize(256).synchronous())) {
      McapChannel<Reading> channel = writer.channel(name.replace(".mcap", ""), Reading.class);
      for (int i = 0; i < count; i++) {
        channel.write(i, i, i, new Reading(i));
      }
    }
    return file;
  }

  /** Flips a byte in the last message's record: the summary stays intact, its chunk fails its CRC. */
  private static void corruptLastChunk(Path file) throws Exception {
    byte[] bytes = Files.readAllBytes(file);
    long summaryStart = ByteBuffer.wrap(bytes, bytes.length - 8 - 20, 8).order(ByteOrder.LITTLE_ENDIAN).getLong();
    long message = findLastMessageRecord(bytes, summaryStart);
    try (RandomAccessFile raf = new RandomAccessFile(file.toFile(), "rw")) {
      raf.seek(message + 30); // the last byte of its publish_time
      int b = raf.read();
      raf.seek(message + 30);
      raf.write(b ^ 0x01);
    }
    try (McapReader reader = McapReader.open(file)) {
      assertThrows(McapFormatException.class, () -> reader.messages().count(), "the chunk fails its CRC");
    }
  }

  /** The offset of the last Message record's opcode ({"value": in its JSON follows it). */
  private static long findLastMessageRecord(byte[] bytes, long before) {
    byte[] json = "{\"value\":".getBytes(StandardCharsets.UTF_8);
    for (int i = (int) before - json.length; i >= 0; i--) {
      boolean match = true;
      for (int j = 0; j < json.length && match; j++) {
        match = bytes[i + j] == json[j];
      }
      if (match) {
        return i - (1 + 8 + 2 + 4 + 8 + 8);
      }
    }
    throw new AssertionError("no message found");
  }

  private List<Path> filesIn() throws Exception {
    try (Stream<Path> files = Files.list(dir)) {
      return files.sorted().toList();
    }
  }

  @Test
  void aFailedMergeKeepsTheEarlierOutputAndLeavesNothingBehind() throws Exception {
    Path robot = recording("robot.mcap", 200);
    Path worker = recording("worker.mcap", 200);
    Path output = dir.resolve("run.mcap");
    McapMerge.merge(List.of(robot, worker), output);
    byte[] earlier = Files.readAllBytes(output);
    List<Path> before = filesIn();

    corruptLastChunk(worker);
    assertThrows(McapFormatException.class, () -> McapMerge.merge(List.of(robot, worker), output));

    assertArrayEquals(earlier, Files.readAllBytes(output), "the earlier merge at the output path is kept");
    assertEquals(before, filesIn(), "no partial or temporary file is left");
  }

  @Test
  void aFailedMergeCreatesNoOutput() throws Exception {
    Path robot = recording("robot.mcap", 200);
    Path worker = recording("worker.mcap", 200);
    corruptLastChunk(worker);
    Path output = dir.resolve("fresh.mcap");

    assertThrows(McapFormatException.class, () -> McapMerge.merge(List.of(robot, worker), output));

    assertFalse(Files.exists(output), "no unfinished file at the output path");
    assertEquals(List.of(robot, worker), filesIn());
  }

  /**
   * A merge is written beside its output until it is complete, under a name of its own that no
   * file there has: a user's file named like the output with a suffix ({@code run.mcap.partial})
   * is neither replaced nor deleted, by a merge that succeeds nor by one that fails, and may
   * itself be an input.
   */
  @Test
  void aUsersFileBesideTheOutputIsNeverTheMergesPartialFile() throws Exception {
    Path robot = recording("robot.mcap", 200);
    Path output = dir.resolve("run.mcap");
    Path users = dir.resolve("run.mcap.partial");
    byte[] notes = "the user's own notes, not a merge".getBytes(StandardCharsets.UTF_8);
    Files.write(users, notes);

    McapMerge.merge(List.of(robot), output);

    assertArrayEquals(notes, Files.readAllBytes(users), "a merge that succeeds leaves the user's file as it was");
    assertEquals(List.of(robot, output, users), filesIn(), "and no file of its own beside the output");

    Path worker = recording("worker.mcap", 200);
    corruptLastChunk(worker);
    assertThrows(McapFormatException.class, () -> McapMerge.merge(List.of(robot, worker), output));
    assertArrayEquals(notes, Files.readAllBytes(users), "a merge that fails leaves the user's file as it was");
    assertEquals(List.of(robot, output, users, worker), filesIn(), "and no file of its own beside the output");

    Path copy = dir.resolve("robot-copy.mcap.partial");
    Files.copy(robot, copy);
    Path other = dir.resolve("robot-copy.mcap");
    McapMerge.Result merged = McapMerge.merge(List.of(copy), other);
    assertEquals(200, merged.messages(), "an input named like the output with the suffix is merged");
  }
}

package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;

import java.nio.file.Path;
import java.util.List;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * {@link McapMerge}'s order for equal log times: by sequence number, then input order, also when
 * one input holds the equal times in another order (a writer fed by several threads writes them
 * in the order they reached it).
 */
class MergeTieOrderTest {
  @TempDir Path dir;

  record Reading(int value) {}

  /** Writes (topic, log time, sequence) triples, in the order given. */
  private Path file(String name, String topic, long[][] messages) throws Exception {
    Path file = dir.resolve(name);
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().synchronous())) {
      McapChannel<Reading> channel = writer.channel(topic, Reading.class);
      for (long[] m : messages) {
        channel.write(m[0], m[0], m[1], new Reading((int) m[1]));
      }
    }
    return file;
  }

  /** The merged file's messages as written (a reader gives equal log times in file order). */
  private static List<Long> sequencesInFileOrder(Path merged) throws Exception {
    try (McapReader reader = McapReader.open(merged)) {
      return reader.messages().map(McapMessage::sequence).toList();
    }
  }

  @Test
  void equalLogTimesComeBySequenceAcrossAndWithinInputs() throws Exception {
    Path robot = file("robot.mcap", "encoders", new long[][] {{5, 3}, {5, 1}, {7, 6}});
    Path worker = file("worker.mcap", "planner", new long[][] {{5, 2}, {7, 4}, {7, 5}});
    Path merged = dir.resolve("merged.mcap");

    McapMerge.merge(List.of(robot, worker), merged);

    assertEquals(List.of(1L, 2L, 3L, 4L, 5L, 6L), sequencesInFileOrder(merged),
        "log time, then sequence number, then input order");
  }

  @Test
  void oneInputsEqualLogTimesComeBySequence() throws Exception {
    Path single = file("single.mcap", "encoders", new long[][] {{5, 9}, {5, 8}, {5, 7}, {6, 1}});
    Path merged = dir.resolve("single-merged.mcap");

    McapMerge.merge(List.of(single), merged);

    assertEquals(List.of(7L, 8L, 9L, 1L), sequencesInFileOrder(merged));
  }
}

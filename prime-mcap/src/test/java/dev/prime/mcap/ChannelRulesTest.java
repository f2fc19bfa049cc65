package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.IOException;
import java.nio.file.Path;
import java.util.List;
import java.util.Map;
import java.util.stream.Collectors;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/** What McapWriter and McapChannel promise about topics, types, times and sequence numbers. */
class ChannelRulesTest {
  @TempDir Path dir;

  @Test
  void aTopicHasOneTypeAndOneChannel() throws IOException {
    try (McapWriter writer = McapWriter.open(dir.resolve("one.mcap"))) {
      McapChannel<Double> speed = writer.channel("speed", Double.class);
      assertSame(speed, writer.channel("speed", ValueType.of(Double.class)), "same topic, same type");
      IllegalArgumentException e =
          assertThrows(IllegalArgumentException.class, () -> writer.channel("speed", String.class));
      assertTrue(e.getMessage().contains("'speed'"), e.getMessage());
      assertTrue(e.getMessage().contains("java.lang.Double"), e.getMessage());
      assertTrue(e.getMessage().contains("java.lang.String"), e.getMessage());
    }
  }

  @Test
  void aFileHoldsAtMost65535ChannelsAndTheNextTopicIsRefused() throws IOException {
    Path file = dir.resolve("many.mcap");
    int most = 65_535;
    try (McapWriter writer = McapWriter.open(file)) {
      McapChannel<Integer> first = writer.channel("t0", Integer.class);
      for (int i = 1; i < most; i++) {
        writer.channel("t" + i, Integer.class);
      }
      IllegalArgumentException e =
          assertThrows(IllegalArgumentException.class, () -> writer.channel("one-more", Integer.class));
      assertTrue(e.getMessage().contains("at most 65535 channels"), e.getMessage());
      assertSame(first, writer.channel("t0", Integer.class), "a topic defined before is still given");
      assertTrue(first.write(1, 1, 0, 42), "the channels defined still record");
    }
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(
          List.of(42),
          reader.messages("t0", Integer.class).map(TypedMessage::value).collect(Collectors.toList()));
      assertTrue(
          reader.channels().stream().noneMatch(c -> c.topic().equals("one-more")),
          "the refused topic has no channel");
    }
  }

  @Test
  void negativeTimesAreRefusedNamingTheTopicAndNothingIsWritten() throws IOException {
    Path file = dir.resolve("times.mcap");
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().synchronous())) {
      McapChannel<Integer> count = writer.channel("count", Integer.class);
      IllegalArgumentException log =
          assertThrows(IllegalArgumentException.class, () -> count.write(-1, 0, 0, 1));
      assertTrue(log.getMessage().contains("'count'"), log.getMessage());
      IllegalArgumentException publish =
          assertThrows(IllegalArgumentException.class, () -> count.write(0, -1, 0, 2));
      assertTrue(publish.getMessage().contains("'count'"), publish.getMessage());
      assertTrue(count.write(5, 5, 0, 3));
    }
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(
          List.of(3),
          reader.messages("count", Integer.class).map(TypedMessage::value).collect(Collectors.toList()));
    }
  }

  @Test
  void aSequenceNumberKeepsItsLow32Bits() throws IOException {
    Path file = dir.resolve("sequence.mcap");
    long[] written = {7, (1L << 32) + 5, 0xFFFF_FFFFL, -1L};
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().synchronous())) {
      McapChannel<Integer> count = writer.channel("count", Integer.class);
      for (int i = 0; i < written.length; i++) {
        count.write(i, i, written[i], i);
      }
    }
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(
          List.of(7L, 5L, 0xFFFF_FFFFL, 0xFFFF_FFFFL),
          reader.messages().map(McapMessage::sequence).collect(Collectors.toList()));
    }
  }

  @Test
  void aClosedWriterRefusesChannelsMetadataAndValuesNamingTheFile() throws IOException {
    Path file = dir.resolve("closed.mcap");
    McapWriter writer = McapWriter.open(file);
    McapChannel<Integer> count = writer.channel("count", Integer.class);
    assertTrue(count.write(1, 1, 0, 1));
    writer.close();
    writer.close(); // twice does nothing
    IllegalStateException value = assertThrows(IllegalStateException.class, () -> count.write(2, 2, 1, 2));
    assertTrue(value.getMessage().contains(file.toString()), value.getMessage());
    assertTrue(value.getMessage().contains("'count'"), value.getMessage());
    IllegalStateException channel =
        assertThrows(IllegalStateException.class, () -> writer.channel("late", Integer.class));
    assertTrue(channel.getMessage().contains(file + " is closed"), channel.getMessage());
    IllegalStateException metadata =
        assertThrows(IllegalStateException.class, () -> writer.metadata("late", Map.of("a", "b")));
    assertTrue(metadata.getMessage().contains(file + " is closed"), metadata.getMessage());
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(1, reader.messageCount("count"), "the file keeps what was written before the close");
      assertEquals(List.of(), reader.metadata("late"));
    }
  }
}

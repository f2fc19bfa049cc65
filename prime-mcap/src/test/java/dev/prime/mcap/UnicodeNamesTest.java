package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.nio.file.Path;
import java.util.List;
import java.util.Map;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.function.Executable;
import org.junit.jupiter.api.io.TempDir;

/**
 * MCAP strings (topics, metadata names, keys and values) are UTF-8. Any Unicode name is written
 * and read back as given; a Java string that is not Unicode text (an unpaired UTF-16 surrogate,
 * which UTF-8 cannot hold) is refused when given, naming it, instead of being written as
 * {@code ?}: two such topics would become one name in the file, and a topic would not be found
 * under the name it was recorded with.
 */
class UnicodeNamesTest {
  @TempDir Path dir;

  @Test
  void unicodeTopicsAndMetadataReadBackAsGiven() throws Exception {
    Path file = dir.resolve("unicode.mcap");
    String topic = "odometría/車輪/🤖";
    try (McapWriter writer = McapWriter.open(file)) {
      writer.channel(topic, ValueType.of(Double.class), Map.of("clé", "värde 🚀")).write(1, 1, 1, 0.5);
      writer.metadata("run.説明", Map.of("ziel", "2,1 → 3,4"));
    }
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(List.of(0.5), reader.messages(topic, Double.class).map(TypedMessage::value).toList());
      assertEquals("värde 🚀", reader.channel(topic).orElseThrow().metadata().get("clé"));
      assertEquals(List.of(Map.of("ziel", "2,1 → 3,4")), reader.metadata("run.説明"));
    }
  }

  @Test
  void anUnpairedSurrogateIsRefusedWhereItIsGiven() throws Exception {
    try (McapWriter writer = McapWriter.open(dir.resolve("surrogates.mcap"))) {
      List<Executable> refused = List.of(
          () -> writer.channel("wheel\uD800", Double.class),
          () -> writer.channel("wheel", ValueType.of(Double.class), Map.of("key\uDC00", "v")),
          () -> writer.channel("wheel", ValueType.of(Double.class), Map.of("key", "\uDBFFv")),
          () -> writer.metadata("run\uD83E", Map.of()),
          () -> writer.metadata("run", Map.of("\uDD16", "v")),
          () -> writer.metadata("run", Map.of("k", "v\uD800")));
      for (Executable call : refused) {
        IllegalArgumentException e = assertThrows(IllegalArgumentException.class, call);
        assertTrue(e.getMessage().contains("unpaired surrogate"), e.getMessage());
      }
      assertTrue(writer.channel("wheel", Double.class).write(1, 1, 1, 1.0), "nothing refused was defined");
    }
  }
}

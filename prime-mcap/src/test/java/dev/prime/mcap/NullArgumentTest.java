package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.RecordingOptions;
import dev.prime.liberty.LibertyCore;
import java.lang.reflect.Type;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.Arrays;
import java.util.HashMap;
import java.util.Map;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.function.Executable;
import org.junit.jupiter.api.io.TempDir;

/**
 * A null given to a public entry point of the module is refused at once with a {@link
 * NullPointerException} that names the parameter, not one from deep inside that names nothing.
 */
class NullArgumentTest {
  @TempDir Path dir;

  private static void refusedNaming(String parameter, Executable call) {
    NullPointerException e = assertThrows(NullPointerException.class, call);
    String message = String.valueOf(e.getMessage());
    assertTrue(message.startsWith(parameter + " must not be null"), message);
  }

  @Test
  void valueTypesRefuseANullType() {
    refusedNaming("type", () -> ValueType.of(null));
    refusedNaming("type", () -> ValueType.ofType((Type) null));
  }

  @Test
  void readersRefuseANullPath() {
    refusedNaming("path", () -> McapReader.open(null));
    refusedNaming("path", () -> McapReader.openUnfinished(null));
    refusedNaming("first", () -> McapReader.recordingFiles(null));
    refusedNaming("first", () -> McapWriter.rotatedPath(null, 1));
  }

  @Test
  void aReaderRefusesANullTypeWhenAsked() throws Exception {
    Path file = dir.resolve("run.mcap");
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().synchronous())) {
      assertTrue(writer.channel("ticks", Integer.class).write(1, 1, 1, 7));
    }
    try (McapReader reader = McapReader.open(file)) {
      refusedNaming("type", () -> reader.messages("ticks", (ValueType<Integer>) null));
    }
  }

  @Test
  void aWriterRefusesANullChannelMetadataMap() throws Exception {
    try (McapWriter writer = McapWriter.open(dir.resolve("run.mcap"), McapWriterOptions.defaults().synchronous())) {
      refusedNaming("metadata", () -> writer.channel("ticks", ValueType.of(Integer.class), (Map<String, String>) null));
    }
  }

  /**
   * A null type given for a name is refused naming the name, by {@link RecordingMcap#write} and
   * {@link RecordingMcap#stream}, before the file at the path is touched.
   */
  @Test
  void recordingMcapRefusesANullTypeNamingItsName() throws Exception {
    Path file = dir.resolve("run.mcap");
    try (McapWriter earlier = McapWriter.open(file, McapWriterOptions.defaults().synchronous())) {
      assertTrue(earlier.channel("earlier", Integer.class).write(1, 1, 1, 7));
    }
    byte[] before = Files.readAllBytes(file);
    Map<String, ValueType<?>> types = new HashMap<>();
    types.put("ticks", null);
    try (PrimeCore core = new LibertyCore(CoreConfig.builder().recording(RecordingOptions.ring(4)).build())) {
      EventBlock<Integer> ticks = new EventBlock<>();
      core.source("ticks", ticks);
      core.start();
      ticks.publish(1);
      refusedNaming("the type given for 'ticks'", () -> RecordingMcap.write(core.recording(), file, types));
      refusedNaming("the type given for 'ticks'",
          () -> RecordingMcap.stream(core.recording(), file, McapWriterOptions.defaults(), types, Map.of()).close());
    }
    assertTrue(Arrays.equals(before, Files.readAllBytes(file)), "the file at the path stays");
  }
}

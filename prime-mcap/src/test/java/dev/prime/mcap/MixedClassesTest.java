package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.RecordingOptions;
import dev.prime.liberty.LibertyCore;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.List;
import java.util.stream.Stream;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * {@link RecordingMcap#write}: a name whose values are of more than one class (a block declared
 * to give a {@code Number}) cannot be one channel; the write is refused naming the name and both
 * classes, and leaves the file at the path as it was: no half-written recording replaces an
 * earlier one.
 */
class MixedClassesTest {
  @TempDir Path dir;

  @Test
  void valuesOfAnotherClassAreRefusedNamingThemAndTheFileIsLeftAsItWas() throws Exception {
    Path file = dir.resolve("run.mcap");
    CoreConfig config = CoreConfig.builder().recording(RecordingOptions.ring(10)).build();
    try (PrimeCore core = new LibertyCore(config)) {
      var ticks = core.chain("ticks", (Integer x) -> x).toBlock();
      var half = core.chain("half", (Integer x) -> {
        Number n;
        if (x % 2 == 0) {
          n = x / 2;
        } else {
          n = x / 2.0;
        }
        return n;
      }).toBlock();
      core.start();
      for (int i = 0; i < 6; i++) {
        ticks.process(i);
      }
      assertEquals(6, RecordingMcap.write(core.recording(), file), "an earlier recording at the path");
      byte[] earlier = Files.readAllBytes(file);
      for (int i = 2; i <= 3; i++) {
        half.process(i); // 1 (Integer), then 1.5 (Double)
      }

      IllegalArgumentException e = assertThrows(IllegalArgumentException.class,
          () -> RecordingMcap.write(core.recording(), file));

      assertArrayEquals(earlier, Files.readAllBytes(file), "the earlier recording at the path is kept");
      assertTrue(e.getMessage().contains("'half'"), e.getMessage());
      assertTrue(e.getMessage().contains("java.lang.Integer") && e.getMessage().contains("java.lang.Double"),
          e.getMessage());
      try (Stream<Path> files = Files.list(dir)) {
        assertEquals(List.of(file), files.toList(), "nothing else is left in the folder");
      }
    }
  }
}

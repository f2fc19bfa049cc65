package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.RecordingOptions;
import dev.prime.liberty.LibertyCore;
import java.nio.file.Path;
import java.time.Duration;
import java.util.List;
import java.util.Map;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * An enum is a channel type (its constants' names); a constant with a body of its own is an
 * instance of an anonymous subclass, whose class is not itself an enum. A recording's channel of
 * such values is typed by the enum, written and streamed like any other.
 */
class EnumWithBodiesTest {
  @TempDir Path dir;

  /** Constants with bodies: {@code Mode.DRIVE.getClass()} is {@code Mode$1}, not {@code Mode}. */
  enum Mode {
    IDLE,
    DRIVE {
      @Override
      double speed() {
        return 1.0;
      }
    },
    DOCK {
      @Override
      double speed() {
        return 0.2;
      }
    };

    double speed() {
      return 0;
    }
  }

  private static PrimeCore core() {
    return new LibertyCore(CoreConfig.builder().recording(RecordingOptions.ring(8)).build());
  }

  @Test
  void writeTypesTheChannelByTheEnum() throws Exception {
    Path file = dir.resolve("modes.mcap");
    try (PrimeCore core = core()) {
      EventBlock<Mode> modes = new EventBlock<>();
      Reader<Mode> read = core.source("mode", modes).reader();
      core.start();
      for (Mode mode : List.of(Mode.DRIVE, Mode.IDLE, Mode.DOCK)) {
        modes.publish(mode);
        assertTrue(read.take(Duration.ofSeconds(20)).isPresent());
      }
      assertEquals(3, RecordingMcap.write(core.recording(), file));
    }
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(ValueType.of(Mode.class).name(), reader.channel("mode").orElseThrow().schema().orElseThrow().name());
      assertEquals(List.of(Mode.DRIVE, Mode.IDLE, Mode.DOCK),
          reader.messages("mode", Mode.class).map(TypedMessage::value).toList());
    }
  }

  @Test
  void streamTypesTheChannelByTheEnum() throws Exception {
    Path file = dir.resolve("streamed-modes.mcap");
    McapRecorder recorder;
    try (PrimeCore core = core()) {
      EventBlock<Mode> modes = new EventBlock<>();
      Reader<Mode> read = core.source("mode", modes).reader();
      core.start();
      recorder = RecordingMcap.stream(core.recording(), file, McapWriterOptions.defaults(), Map.of(), Map.of());
      try (recorder) {
        for (Mode mode : List.of(Mode.DOCK, Mode.IDLE, Mode.DRIVE)) {
          modes.publish(mode);
          assertTrue(read.take(Duration.ofSeconds(20)).isPresent());
        }
      }
    }
    assertEquals(0, recorder.unwritableCount(), "every value has its channel");
    try (McapReader reader = McapReader.open(file)) {
      assertEquals(List.of(Mode.DOCK, Mode.IDLE, Mode.DRIVE),
          reader.messages("mode", Mode.class).map(TypedMessage::value).toList());
    }
  }
}

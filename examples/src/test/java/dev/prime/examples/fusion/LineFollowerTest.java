package dev.prime.examples.fusion;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.VirtualClock;
import dev.prime.examples.fusion.LineFollower.Steering;
import dev.prime.liberty.LibertyCore;
import dev.prime.optimus.OptimusCore;
import dev.prime.radiant.RadiantCore;
import java.io.IOException;
import java.nio.file.Files;
import java.nio.file.Path;
import java.time.Duration;
import java.util.List;
import java.util.function.Function;
import java.util.stream.Stream;
import org.junit.jupiter.api.Named;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.params.ParameterizedTest;
import org.junit.jupiter.params.provider.MethodSource;

/**
 * The line follower's sensor fusion on a virtual clock: every gyro reading after the first line
 * reading gives exactly one steering command, fused with a line reading no newer than it, and
 * the README shows the fusion as compiled.
 */
class LineFollowerTest {

  static Stream<Named<Function<CoreConfig, PrimeCore>>> media() {
    return Stream.of(
        Named.<Function<CoreConfig, PrimeCore>>of("Liberty", LibertyCore::new),
        Named.<Function<CoreConfig, PrimeCore>>of("Radiant", RadiantCore::new),
        Named.<Function<CoreConfig, PrimeCore>>of(
            "Optimus", config -> OptimusCore.builder().config(config).build()));
  }

  @ParameterizedTest
  @MethodSource("media")
  void everyGyroReadingAfterTheFirstLineReadingSteersOnceWithTheLatestLineReading(
      Function<CoreConfig, PrimeCore> media) throws InterruptedException {
    VirtualClock clock = new VirtualClock();
    List<Steering> commands;
    try (PrimeCore core = media.apply(CoreConfig.builder().clock(clock).build())) {
      commands = LineFollower.run(core, clock, Duration.ofSeconds(10));
    }
    long first = commands.get(0).gyroMillis();
    assertTrue(first >= 50, "gyro readings before the first line reading (50 ms) are dropped: " + first);
    assertEquals((10_000 - first) / 10 + 1, commands.size(), "one command per gyro reading");
    for (int i = 0; i < commands.size(); i++) {
      Steering command = commands.get(i);
      assertEquals(first + 10L * i, command.gyroMillis(), "gyro readings in order, none twice");
      assertTrue(command.lineMillis() % 50 == 0 && command.lineMillis() >= 50, command.toString());
      assertTrue(command.lineMillis() <= command.gyroMillis(), "never a line reading from the future: " + command);
      double expected =
          2.0 * 0.1 * Math.sin(command.lineMillis() / 1000.0)
              - 0.3 * 0.5 * Math.cos(command.gyroMillis() / 1000.0);
      assertEquals(expected, command.turnRate(), 1e-12, command.toString());
    }
  }

  /** The README shows the code between the fusion markers of LineFollower.java, verbatim. */
  @Test
  void readmeShowsTheCompiledFusion() throws IOException {
    String source =
        Files.readString(Path.of("src/main/java/dev/prime/examples/fusion/LineFollower.java"));
    String readme = Files.readString(Path.of("../README.md"));
    String begin = "// fusion:begin\n";
    String end = "    // fusion:end";
    String body = source.substring(source.indexOf(begin) + begin.length(), source.indexOf(end));
    String snippet =
        body.lines()
            .map(line -> line.length() >= 4 ? line.substring(4) : line)
            .reduce("", (a, b) -> a + b + "\n");
    assertTrue(
        readme.contains(snippet),
        "README.md must contain the fusion of LineFollower.java, unindented by 4:\n" + snippet);
  }
}

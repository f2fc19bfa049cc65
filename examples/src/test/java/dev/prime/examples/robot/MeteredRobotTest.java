package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.metrics.PrimeMetrics;
import io.micrometer.core.instrument.simple.SimpleMeterRegistry;
import java.io.ByteArrayOutputStream;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.util.Map;
import org.junit.jupiter.params.ParameterizedTest;
import org.junit.jupiter.params.provider.EnumSource;

/** The robot with its metrics in a Micrometer registry, on every media. */
class MeteredRobotTest {
  @ParameterizedTest
  @EnumSource(Media.class)
  void everyControlStepIsCountedAndTimed(Media media) {
    SimpleMeterRegistry registry = new SimpleMeterRegistry();
    ByteArrayOutputStream bytes = new ByteArrayOutputStream();
    SimulationResult result =
        MeteredRobot.run(media, registry, new PrintStream(bytes, true, StandardCharsets.UTF_8));
    String table = bytes.toString(StandardCharsets.UTF_8);
    assertTrue(result.reached(), table);
    long steps = result.steps();
    // one encoder reading, odometry estimate, collected estimate and guarded command per control
    // step; the planner and the PID run on every step but the last, where the guard's substitute
    // stops the motors at the goal
    Map<String, Long> expected =
        Map.of(
            "encoders", steps,
            "odometry", steps,
            "collect(encoders>odometry)", steps,
            "guard(planner>pid)", steps,
            "planner", steps - 1,
            "pid", steps - 1);
    for (Map.Entry<String, Long> entry : expected.entrySet()) {
      String service = entry.getKey();
      long values = entry.getValue();
      double in =
          registry.get(PrimeMetrics.VALUES_IN).tag("service", service).functionCounter().count();
      assertEquals(values, in, service + " in " + table);
      assertEquals(
          values,
          registry.get(PrimeMetrics.PROCESSING).tag("service", service).timer().count(),
          service + " timed " + table);
      assertEquals(
          0.0,
          registry.get(PrimeMetrics.FAILURES).tag("service", service).functionCounter().count());
      assertEquals(
          media.cliName(),
          registry.get(PrimeMetrics.VALUES_IN).tag("service", service).meter().getId().getTag("media"));
    }
    assertTrue(table.contains("robot on media " + media.cliName() + " reached the goal"), table);
    assertTrue(table.lines().anyMatch(line -> line.trim().startsWith("odometry")), table);
  }
}

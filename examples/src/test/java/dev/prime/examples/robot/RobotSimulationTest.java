package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.liberty.LibertyCore;
import dev.prime.test.PrimeTest;
import java.io.ByteArrayOutputStream;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.util.List;
import org.junit.jupiter.api.Nested;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.params.Parameter;
import org.junit.jupiter.params.ParameterizedClass;
import org.junit.jupiter.params.ParameterizedTest;
import org.junit.jupiter.params.provider.MethodSource;

/**
 * The whole controller, wired by {@link RobotController}, on a real {@link LibertyCore}, and on
 * every media ({@link OnEveryMedia}).
 */
class RobotSimulationTest {
  private static final String CORE = "robot-test";

  static List<Goal> goals() {
    return List.of(new Goal(2, 1), new Goal(-1, 1.5), new Goal(0.5, -2), new Goal(-1.5, -0.2));
  }

  private static String run(Goal goal, SimulationResult[] result) {
    return run(Media.LIBERTY, goal, result);
  }

  private static String run(Media media, Goal goal, SimulationResult[] result) {
    ByteArrayOutputStream trace = new ByteArrayOutputStream();
    try (PrimeCore core = media.create(CoreConfig.builder().name(CORE).build())) {
      result[0] =
          new RobotSimulation(RobotSpec.SMALL_INDOOR)
              .run(
                  core,
                  new Mission(goal, 4000, 50),
                  new PrintStream(trace, true, StandardCharsets.UTF_8));
    }
    return trace.toString(StandardCharsets.UTF_8);
  }

  @ParameterizedTest
  @MethodSource("goals")
  void reachesTheGoalWithinTolerance(Goal goal) {
    SimulationResult[] result = new SimulationResult[1];
    run(goal, result);

    assertTrue(result[0].reached(), "reached: " + result[0]);
    assertTrue(result[0].estimatedError() <= RobotController.TOLERANCE, "odometry: " + result[0]);
    // odometry only counts whole ticks, so the true pose may differ from the estimate a little
    assertTrue(result[0].actualError() <= RobotController.TOLERANCE + 0.01, "true: " + result[0]);
    assertTrue(result[0].steps() < 4000, "steps: " + result[0]);
  }

  @Test
  void sameMissionGivesTheSameTraceAndLeavesNoThreadBehind() {
    SimulationResult[] first = new SimulationResult[1];
    SimulationResult[] second = new SimulationResult[1];

    String a = run(new Goal(2, 1), first);
    String b = run(new Goal(2, 1), second);

    assertEquals(a, b);
    assertEquals(first[0], second[0]);
    assertTrue(a.lines().count() > 5, a);
    assertTrue(a.strip().endsWith("arrived"), a);
    List<String> left =
        Thread.getAllStackTraces().keySet().stream()
            .map(Thread::getName)
            .filter(name -> name.startsWith("prime-" + CORE + "-"))
            .toList();
    assertEquals(List.of(), left);
  }

  /**
   * Every goal on every media ({@link PrimeTest}: one run per media, each with a fresh core)
   * gives the trace and the summary Liberty gives.
   */
  @Nested
  @ParameterizedClass
  @MethodSource("dev.prime.examples.robot.RobotSimulationTest#goals")
  class OnEveryMedia {
    @Parameter Goal goal;

    @PrimeTest(setup = RobotCores.class)
    void givesTheSameTraceAndSummaryAsLiberty(PrimeCore core) {
      SimulationResult[] liberty = new SimulationResult[1];
      String expected = run(Media.LIBERTY, goal, liberty);
      ByteArrayOutputStream trace = new ByteArrayOutputStream();

      SimulationResult result =
          new RobotSimulation(RobotSpec.SMALL_INDOOR)
              .run(
                  core,
                  new Mission(goal, 4000, 50),
                  new PrintStream(trace, true, StandardCharsets.UTF_8));

      assertEquals(expected, trace.toString(StandardCharsets.UTF_8));
      assertEquals(liberty[0], result);
    }
  }
}

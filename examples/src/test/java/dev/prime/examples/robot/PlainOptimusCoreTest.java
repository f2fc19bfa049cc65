package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.PrimeCore;
import dev.prime.liberty.LibertyCore;
import dev.prime.optimus.OptimusCore;
import java.io.ByteArrayOutputStream;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import org.junit.jupiter.api.Test;

/**
 * The README's one-line switch: the robot's own records cross Redis on a plain {@code new
 * OptimusCore()}, with no codec configured.
 */
class PlainOptimusCoreTest {

  private static String run(PrimeCore core, SimulationResult[] result) {
    ByteArrayOutputStream trace = new ByteArrayOutputStream();
    try (core) {
      result[0] =
          new RobotSimulation(RobotSpec.SMALL_INDOOR)
              .run(
                  core,
                  new Mission(new Goal(1.5, -0.5), 4000, 50),
                  new PrintStream(trace, true, StandardCharsets.UTF_8));
    }
    return trace.toString(StandardCharsets.UTF_8);
  }

  @Test
  void theRobotRunsOnANewOptimusCoreAsOnLiberty() {
    SimulationResult[] liberty = new SimulationResult[1];
    String expected = run(new LibertyCore(), liberty);

    SimulationResult[] optimus = new SimulationResult[1];
    String trace = run(new OptimusCore(), optimus);

    assertTrue(optimus[0].reached(), "reached: " + optimus[0]);
    assertEquals(expected, trace);
    assertEquals(liberty[0], optimus[0]);
  }
}

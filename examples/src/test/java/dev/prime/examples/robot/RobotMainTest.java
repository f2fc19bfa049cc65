package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.ByteArrayOutputStream;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import org.junit.jupiter.api.Test;

class RobotMainTest {
  private final ByteArrayOutputStream out = new ByteArrayOutputStream();
  private final ByteArrayOutputStream err = new ByteArrayOutputStream();

  private int run(String... args) {
    return RobotMain.run(
        args,
        new PrintStream(out, true, StandardCharsets.UTF_8),
        new PrintStream(err, true, StandardCharsets.UTF_8));
  }

  private String out() {
    return out.toString(StandardCharsets.UTF_8);
  }

  private String err() {
    return err.toString(StandardCharsets.UTF_8);
  }

  @Test
  void unknownMediaExitsWithTwoAndPrintsUsage() {
    assertEquals(2, run("--media", "warp"));
    assertTrue(err().startsWith("error: unknown media 'warp'; known media: liberty"), err());
    assertTrue(err().contains("usage: robot"), err());
    assertEquals("", out());
  }

  @Test
  void helpPrintsUsageAndExitsWithZero() {
    assertEquals(0, run("--help"));
    assertTrue(out().startsWith("usage: robot"), out());
  }

  @Test
  void tooFewStepsExitsWithOneAndSaysSo() {
    assertEquals(1, run("--steps", "5"));
    assertTrue(out().contains("did NOT reach goal (x=2.000, y=1.000) after 5 steps"), out());
  }

  @Test
  void defaultRunReachesTheGoalAndPrintsTheSummary() {
    assertEquals(0, run());
    String text = out();
    assertTrue(text.startsWith("robot on media liberty: driving from"), text);
    assertTrue(text.contains("reached goal (x=2.000, y=1.000) after "), text);
    assertTrue(text.contains("distance error to goal: "), text);
  }

  @Test
  void malformedRedisUrlExitsWithTwoAndSaysSo() {
    assertEquals(2, run("--media", "optimus", "--redis", "localhost:6379"));
    assertTrue(err().startsWith("error: --redis: "), err());
    assertTrue(err().contains("usage: robot"), err());
    assertEquals("", out());
  }

  @Test
  void unreachableRedisExitsWithThreeAndSaysSo() {
    // port 1 is reserved (tcpmux) and closed on any ordinary machine
    assertEquals(3, run("--media", "optimus", "--redis", "redis://127.0.0.1:1", "--steps", "5"));
    assertTrue(err().startsWith("error: cannot reach Redis at "), err());
  }

  @Test
  void optimusRunsOnAnEmbeddedRedisByDefault() {
    assertEquals(0, run("--media", "optimus", "--goal", "0.5,0.2"));
    assertTrue(out().startsWith("robot on media optimus: driving from"), out());
    assertTrue(out().contains("reached goal (x=0.500, y=0.200) after "), out());
  }
}

package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.mcap.McapReader;
import java.io.ByteArrayOutputStream;
import java.io.IOException;
import java.io.OutputStream;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

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

  /**
   * A run that fails part way (here its output, once the recording has started: an unchecked
   * failure, as a closed pipe below the trace) still finishes its recording: the file is complete
   * and its path is free for the next run.
   */
  @Test
  void aRunThatFailsStillFinishesItsRecording(@TempDir Path dir) throws IOException {
    Path file = dir.resolve("failed.mcap");
    IllegalStateException broken = new IllegalStateException("the trace's output is closed (simulated)");
    OutputStream failing =
        new OutputStream() {
          @Override
          public void write(int b) {
            write(new byte[] {(byte) b}, 0, 1);
          }

          @Override
          public void write(byte[] bytes, int offset, int length) {
            if (Files.exists(file)) {
              throw broken; // the recording has started: the first trace line fails
            }
            out.write(bytes, offset, length);
          }
        };

    IllegalStateException thrown =
        assertThrows(
            IllegalStateException.class,
            () ->
                RobotMain.run(
                    new String[] {"--trace-every", "1", "--record", file.toString()},
                    new PrintStream(failing, true, StandardCharsets.UTF_8),
                    new PrintStream(err, true, StandardCharsets.UTF_8)));

    assertSame(broken, thrown, "the run's failure is the one thrown");
    assertTrue(out().startsWith("robot on media liberty: driving from"), out());
    try (McapReader reader = McapReader.open(file)) {
      assertTrue(reader.statistics().messageCount() > 0, "the values recorded before the failure are in the file");
    }
    assertFalse(Files.exists(dir.resolve("failed.mcap.lock")), "the recording's path is free again");
  }
}

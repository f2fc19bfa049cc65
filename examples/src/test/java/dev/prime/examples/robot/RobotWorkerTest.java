package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.BufferedReader;
import java.io.ByteArrayInputStream;
import java.io.ByteArrayOutputStream;
import java.io.InputStreamReader;
import java.io.PipedInputStream;
import java.io.PipedOutputStream;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.util.List;
import java.util.concurrent.ExecutorService;
import java.util.concurrent.Executors;
import java.util.concurrent.Future;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;

/**
 * The two-process robot with both "processes" in this JVM: a {@link RobotWorker} hosting the
 * planner and a {@link RobotMain} leaving the planner to it, on one embedded Redis. (The same
 * with two JVMs is prime-optimus's TwoProcessTest.)
 */
class RobotWorkerTest {

  private static List<String> afterHeader(String output, int headerLines) {
    List<String> lines = output.lines().toList();
    return lines.subList(headerLines, lines.size());
  }

  private static String text(ByteArrayOutputStream bytes) {
    return bytes.toString(StandardCharsets.UTF_8);
  }

  @Test
  void robotWithItsPlannerInAWorkerDrivesAsOnLiberty() throws Exception {
    ByteArrayOutputStream libertyOut = new ByteArrayOutputStream();
    PrintStream quiet = new PrintStream(new ByteArrayOutputStream(), true, StandardCharsets.UTF_8);
    String[] mission = {"--goal", "-1,0.5", "--trace-every", "25"};
    assertEquals(
        0,
        RobotMain.run(
            mission, new PrintStream(libertyOut, true, StandardCharsets.UTF_8), quiet));

    ExecutorService threads = Executors.newCachedThreadPool();
    try {
      PipedOutputStream stop = new PipedOutputStream();
      PipedInputStream workerIn = new PipedInputStream(stop);
      PipedInputStream workerOutput = new PipedInputStream();
      PrintStream workerOut =
          new PrintStream(new PipedOutputStream(workerOutput), true, StandardCharsets.UTF_8);
      ByteArrayOutputStream workerErr = new ByteArrayOutputStream();
      // no --redis: the worker starts an embedded Redis and names it in its READY line
      String[] workerArgs = {"--hosts", "planner", "--goal", "-1,0.5", "--name", "robot-w"};
      Future<Integer> worker =
          threads.submit(
              () ->
                  RobotWorker.run(
                      workerArgs,
                      workerIn,
                      workerOut,
                      new PrintStream(workerErr, true, StandardCharsets.UTF_8)));
      BufferedReader workerLines =
          new BufferedReader(new InputStreamReader(workerOutput, StandardCharsets.UTF_8));
      String ready = threads.submit(workerLines::readLine).get(60, TimeUnit.SECONDS);
      String readyPrefix = "READY robot worker hosting [planner] of core 'robot-w' on ";
      assertTrue(ready.startsWith(readyPrefix), ready + text(workerErr));
      String redisUrl = ready.substring(readyPrefix.length());

      String[] robotArgs = {
        "--media", "optimus", "--redis", redisUrl, "--remote", "planner", "--name",
        "robot-w", "--goal", "-1,0.5", "--trace-every", "25"
      };
      // twice: the planner holds no state, and nothing of the first run is left in the way
      for (int run = 1; run <= 2; run++) {
        ByteArrayOutputStream optimusOut = new ByteArrayOutputStream();
        Future<Integer> robot =
            threads.submit(
                () ->
                    RobotMain.run(
                        robotArgs,
                        new PrintStream(optimusOut, true, StandardCharsets.UTF_8),
                        quiet));
        // without the worker's planner the robot could not take a single step
        assertEquals(0, robot.get(120, TimeUnit.SECONDS), "run " + run + ": " + text(optimusOut));
        assertEquals(
            afterHeader(text(libertyOut), 1), afterHeader(text(optimusOut), 2), "run " + run);
        assertTrue(
            text(optimusOut).contains("leaving [planner] to a robot worker"), text(optimusOut));
      }

      stop.write("STOP\n".getBytes(StandardCharsets.UTF_8));
      stop.flush();
      assertEquals(0, worker.get(30, TimeUnit.SECONDS), text(workerErr));
      assertEquals("STOPPED", threads.submit(workerLines::readLine).get(30, TimeUnit.SECONDS));
    } finally {
      threads.shutdownNow();
      assertTrue(threads.awaitTermination(30, TimeUnit.SECONDS));
    }
  }

  @Test
  void workerNeedsItsServices() {
    ByteArrayOutputStream err = new ByteArrayOutputStream();
    int code =
        RobotWorker.run(
            new String[] {"--redis", "redis://127.0.0.1:6379"},
            new ByteArrayInputStream(new byte[0]),
            new PrintStream(new ByteArrayOutputStream(), true, StandardCharsets.UTF_8),
            new PrintStream(err, true, StandardCharsets.UTF_8));

    assertEquals(2, code);
    assertTrue(
        text(err).startsWith("error: --hosts is required: the services this worker runs"),
        text(err));
    assertTrue(text(err).contains("usage: robot-worker"), text(err));
  }
}

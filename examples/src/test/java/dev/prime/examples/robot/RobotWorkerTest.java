package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.optimus.EmbeddedRedis;
import java.io.BufferedReader;
import java.io.ByteArrayInputStream;
import java.io.ByteArrayOutputStream;
import java.io.IOException;
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
    try (EmbeddedRedis redis = EmbeddedRedis.start()) {
      PipedOutputStream stop = new PipedOutputStream();
      PipedInputStream workerIn = new PipedInputStream(stop);
      PipedInputStream workerOutput = new PipedInputStream();
      PrintStream workerOut =
          new PrintStream(new PipedOutputStream(workerOutput), true, StandardCharsets.UTF_8);
      ByteArrayOutputStream workerErr = new ByteArrayOutputStream();
      String[] workerArgs = {
        "--redis", redis.getUri(), "--hosts", "planner", "--goal", "-1,0.5", "--name", "robot-w"
      };
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
      assertEquals(
          "READY robot worker hosting [planner] of core 'robot-w'", ready, text(workerErr));

      ByteArrayOutputStream optimusOut = new ByteArrayOutputStream();
      String[] robotArgs = {
        "--media", "optimus", "--redis", redis.getUri(), "--remote", "planner", "--name",
        "robot-w", "--goal", "-1,0.5", "--trace-every", "25"
      };
      Future<Integer> robot =
          threads.submit(
              () ->
                  RobotMain.run(
                      robotArgs,
                      new PrintStream(optimusOut, true, StandardCharsets.UTF_8),
                      quiet));
      // without the worker's planner the robot could not take a single step
      assertEquals(0, robot.get(120, TimeUnit.SECONDS), text(optimusOut));
      assertEquals(afterHeader(text(libertyOut), 1), afterHeader(text(optimusOut), 2));
      assertTrue(
          text(optimusOut).contains("leaving [planner] to a robot worker"), text(optimusOut));

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
  void workerNeedsARedisAndItsServices() throws IOException {
    ByteArrayOutputStream err = new ByteArrayOutputStream();
    int code =
        RobotWorker.run(
            new String[] {"--hosts", "planner"},
            new ByteArrayInputStream(new byte[0]),
            new PrintStream(new ByteArrayOutputStream(), true, StandardCharsets.UTF_8),
            new PrintStream(err, true, StandardCharsets.UTF_8));

    assertEquals(2, code);
    assertTrue(
        text(err).startsWith("error: --redis URL is required: the Redis shared with the robot"),
        text(err));
    assertTrue(text(err).contains("usage: robot-worker"), text(err));
  }
}

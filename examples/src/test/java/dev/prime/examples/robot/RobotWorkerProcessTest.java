package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.jupiter.api.Assertions.assertTrue;
import static org.junit.jupiter.api.Assumptions.assumeFalse;

import java.io.ByteArrayOutputStream;
import java.io.IOException;
import java.io.OutputStream;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.List;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;

/**
 * {@link RobotWorker} as a real JVM, the way systemd or Docker run it: with its standard input
 * closed it keeps serving, SIGTERM closes it cleanly (exit code 143, after {@code STOPPED}), as
 * Ctrl-C's SIGINT does (exit code 130), and a line {@code STOP} stops it with exit code 0.
 */
class RobotWorkerProcessTest {

  private static final String READY_PREFIX =
      "READY robot worker hosting [planner] of core 'robot-p' on ";

  private static WorkerJvm start(boolean stdinClosed) throws IOException {
    return WorkerJvm.start(
        stdinClosed, "--hosts", "planner", "--goal", "-1,0.5", "--name", "robot-p");
  }

  @Test
  void workerWithClosedStdinServesAndStopsOnSigterm() throws Exception {
    WorkerJvm worker = start(true);
    try {
      String redisUrl = worker.awaitLine(READY_PREFIX, 60).substring(READY_PREFIX.length());
      // stdin was /dev/null from the start: the worker is still there to plan every step
      String[] robotArgs = {
        "--media", "optimus", "--redis", redisUrl, "--remote", "planner", "--name", "robot-p",
        "--goal", "-1,0.5", "--trace-every", "25"
      };
      ByteArrayOutputStream robotOut = new ByteArrayOutputStream();
      PrintStream quiet =
          new PrintStream(new ByteArrayOutputStream(), true, StandardCharsets.UTF_8);
      int robot =
          RobotMain.run(robotArgs, new PrintStream(robotOut, true, StandardCharsets.UTF_8), quiet);
      String trace = robotOut.toString(StandardCharsets.UTF_8);
      assertEquals(0, robot, trace + worker.output());
      assertTrue(trace.contains("leaving [planner] to a robot worker"), trace);
      assertTrue(worker.process().isAlive(), worker.output());

      // SIGTERM, as Process.destroy() sends, but leaving our end of its output open to read on
      assertTrue(worker.process().toHandle().destroy(), "SIGTERM could not be sent");
      assertTrue(worker.process().waitFor(30, TimeUnit.SECONDS), "still running: " + worker.output());
      assertEquals(143, worker.process().exitValue(), worker.output());
      assertNotNull(worker.awaitLine("STOPPED", 10));
    } finally {
      worker.process().destroyForcibly();
    }
  }

  /** Whether the process ignores SIGINT (on Linux; elsewhere assumed not to). */
  private static boolean ignoresSigint(long pid) throws IOException {
    Path status = Path.of("/proc", Long.toString(pid), "status");
    if (!Files.exists(status)) {
      return false;
    }
    for (String line : Files.readAllLines(status)) {
      if (line.startsWith("SigIgn:")) {
        return (Long.parseUnsignedLong(line.substring(7).trim(), 16) & (1L << 1)) != 0; // SIGINT = 2
      }
    }
    return false;
  }

  @Test
  void workerStopsOnCtrlCWithExitCode130() throws Exception {
    WorkerJvm worker = start(true);
    try {
      worker.awaitLine(READY_PREFIX, 60);
      long pid = worker.process().pid();
      assumeFalse(ignoresSigint(pid),
          "the worker JVM ignores SIGINT (started as a background job without job control), so"
              + " no Ctrl-C can reach it here");
      Process kill = new ProcessBuilder("kill", "-INT", Long.toString(pid)).start();
      assertTrue(kill.waitFor(10, TimeUnit.SECONDS), "kill -INT did not end");
      assertEquals(0, kill.exitValue(), "kill -INT " + pid + " failed");
      assertTrue(worker.process().waitFor(30, TimeUnit.SECONDS), "still running: " + worker.output());
      assertEquals(130, worker.process().exitValue(), worker.output());
      assertNotNull(worker.awaitLine("STOPPED", 10));
    } finally {
      worker.process().destroyForcibly();
    }
  }

  @Test
  void workerStopsOnStopLineWithExitCodeZero() throws Exception {
    WorkerJvm worker = start(false);
    try {
      worker.awaitLine(READY_PREFIX, 60);
      OutputStream stdin = worker.process().getOutputStream();
      stdin.write("hello\nSTOP\n".getBytes(StandardCharsets.UTF_8));
      stdin.flush();
      assertTrue(worker.process().waitFor(30, TimeUnit.SECONDS), "still running: " + worker.output());
      assertEquals(0, worker.process().exitValue(), worker.output());
      assertNotNull(worker.awaitLine("STOPPED", 10));
      List<String> errors =
          worker.output().lines().filter(line -> line.contains("Exception")).toList();
      assertEquals(List.of(), errors, worker.output());
    } finally {
      worker.process().destroyForcibly();
    }
  }
}

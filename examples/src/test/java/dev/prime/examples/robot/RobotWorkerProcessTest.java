package dev.prime.examples.robot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.io.BufferedReader;
import java.io.ByteArrayOutputStream;
import java.io.File;
import java.io.IOException;
import java.io.InputStreamReader;
import java.io.OutputStream;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.util.List;
import java.util.concurrent.BlockingQueue;
import java.util.concurrent.LinkedBlockingQueue;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;

/**
 * {@link RobotWorker} as a real JVM, the way systemd or Docker run it: with its standard input
 * closed it keeps serving, SIGTERM closes it cleanly (exit code 143, after {@code STOPPED}), and a
 * line {@code STOP} stops it with exit code 0.
 */
class RobotWorkerProcessTest {

  private static final String READY_PREFIX =
      "READY robot worker hosting [planner] of core 'robot-p' on ";

  /** A worker JVM whose output lines are collected by a daemon thread. */
  private record Worker(Process process, BlockingQueue<String> lines, StringBuilder seen) {

    static Worker start(boolean stdinClosed) throws IOException {
      String java = new File(System.getProperty("java.home"), "bin/java").getPath();
      ProcessBuilder builder =
          new ProcessBuilder(
                  java,
                  "-Xmx256m",
                  "-cp",
                  System.getProperty("java.class.path"),
                  RobotWorker.class.getName(),
                  "--hosts",
                  "planner",
                  "--goal",
                  "-1,0.5",
                  "--name",
                  "robot-p")
              .redirectErrorStream(true);
      if (stdinClosed) {
        builder.redirectInput(new File("/dev/null"));
      }
      Process process = builder.start();
      BlockingQueue<String> lines = new LinkedBlockingQueue<>();
      StringBuilder seen = new StringBuilder();
      Thread pump =
          new Thread(
              () -> {
                try (BufferedReader in =
                    new BufferedReader(
                        new InputStreamReader(process.getInputStream(), StandardCharsets.UTF_8))) {
                  for (String line = in.readLine(); line != null; line = in.readLine()) {
                    synchronized (seen) {
                      seen.append(line).append('\n');
                    }
                    lines.add(line);
                  }
                } catch (IOException e) {
                  // the process is gone
                }
              },
              "worker-output");
      pump.setDaemon(true);
      pump.start();
      return new Worker(process, lines, seen);
    }

    /** Waits (bounded) for a line starting with {@code prefix} and returns it. */
    String awaitLine(String prefix, long seconds) throws InterruptedException {
      long deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(seconds);
      for (long left = seconds; left > 0; ) {
        String line = lines.poll(deadline - System.nanoTime(), TimeUnit.NANOSECONDS);
        if (line == null) {
          break;
        }
        if (line.startsWith(prefix)) {
          return line;
        }
        left = deadline - System.nanoTime();
      }
      throw new AssertionError("no line '" + prefix + "...' in " + seconds + " s; output:\n" + output());
    }

    String output() {
      synchronized (seen) {
        return seen.toString();
      }
    }
  }

  @Test
  void workerWithClosedStdinServesAndStopsOnSigterm() throws Exception {
    Worker worker = Worker.start(true);
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

  @Test
  void workerStopsOnStopLineWithExitCodeZero() throws Exception {
    Worker worker = Worker.start(false);
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

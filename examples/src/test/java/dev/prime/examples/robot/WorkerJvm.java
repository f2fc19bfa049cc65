package dev.prime.examples.robot;

import java.io.BufferedReader;
import java.io.File;
import java.io.IOException;
import java.io.InputStreamReader;
import java.nio.charset.StandardCharsets;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.BlockingQueue;
import java.util.concurrent.LinkedBlockingQueue;
import java.util.concurrent.TimeUnit;

/**
 * A {@link RobotWorker} started as a real JVM on this test's class path, its output lines (stdout
 * and stderr together) collected by a daemon thread. The caller destroys the process.
 */
record WorkerJvm(Process process, BlockingQueue<String> lines, StringBuilder seen) {

  /**
   * Starts the worker.
   *
   * @param stdinClosed whether its standard input is {@code /dev/null}, as under systemd or Docker
   * @param workerArgs the worker's command-line arguments
   */
  static WorkerJvm start(boolean stdinClosed, String... workerArgs) throws IOException {
    String java = new File(System.getProperty("java.home"), "bin/java").getPath();
    List<String> command =
        new ArrayList<>(
            List.of(
                java,
                "-Xmx256m",
                "-cp",
                System.getProperty("java.class.path"),
                RobotWorker.class.getName()));
    command.addAll(List.of(workerArgs));
    ProcessBuilder builder = new ProcessBuilder(command).redirectErrorStream(true);
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
    return new WorkerJvm(process, lines, seen);
  }

  /** Waits (bounded) for a line starting with {@code prefix} and returns it. */
  String awaitLine(String prefix, long seconds) throws InterruptedException {
    long deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(seconds);
    while (System.nanoTime() < deadline) {
      String line = lines.poll(deadline - System.nanoTime(), TimeUnit.NANOSECONDS);
      if (line != null && line.startsWith(prefix)) {
        return line;
      }
    }
    throw new AssertionError(
        "no line '" + prefix + "...' in " + seconds + " s; output:\n" + output());
  }

  /** {@return everything the worker printed so far} */
  String output() {
    synchronized (seen) {
      return seen.toString();
    }
  }
}

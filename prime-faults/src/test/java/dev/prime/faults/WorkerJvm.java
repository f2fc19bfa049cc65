package dev.prime.faults;

import java.io.BufferedReader;
import java.io.File;
import java.io.IOException;
import java.io.InputStreamReader;
import java.io.UncheckedIOException;
import java.nio.charset.StandardCharsets;
import java.time.Duration;
import java.util.ArrayList;
import java.util.List;
import java.util.Map;
import java.util.Optional;
import java.util.concurrent.TimeUnit;
import java.util.function.Predicate;

/**
 * A worker JVM running {@link FaultWorkerMain}: {@code java} from {@code java.home}, this test's
 * class path, the given JVM options and arguments. Its standard output and error are kept, line
 * by line, for {@link #awaitLine} and for failure messages; it is killed with SIGKILL
 * ({@link #kill()}, {@code destroyForcibly}) or SIGTERM ({@link #terminate()}, {@code destroy}).
 *
 * <p>Design note: one daemon thread reads the worker's output until it ends; waiting for a line
 * waits on the line list with a deadline. The worker reads its standard input and exits when it
 * ends, so a worker never outlives the JVM that started it. {@link #close()} kills it if still alive.
 */
final class WorkerJvm implements AutoCloseable {
  private final String name;
  private final Process process;
  private final List<String> lines = new ArrayList<>(); // guarded by itself
  private boolean ended; // guarded by lines
  private final Thread pump;

  private WorkerJvm(String name, Process process) {
    this.name = name;
    this.process = process;
    this.pump = new Thread(this::readOutput, "fault-worker-output-" + name);
    pump.setDaemon(true);
    pump.start();
  }

  /**
   * Starts a worker.
   *
   * @param name for messages
   * @param jvmOptions e.g. {@code -Xmx128m}
   * @param environment variables to set (or, with a {@code null} value, to remove)
   * @param args the arguments of {@link FaultWorkerMain}
   */
  static WorkerJvm start(String name, List<String> jvmOptions, Map<String, String> environment, List<String> args) {
    List<String> command = new ArrayList<>();
    command.add(new File(System.getProperty("java.home"), "bin/java").getPath());
    command.addAll(jvmOptions);
    command.add("-cp");
    command.add(System.getProperty("java.class.path"));
    command.add(FaultWorkerMain.class.getName());
    command.addAll(args);
    ProcessBuilder builder = new ProcessBuilder(command).redirectErrorStream(true);
    environment.forEach((key, value) -> {
      if (value == null) builder.environment().remove(key); else builder.environment().put(key, value);
    });
    try {
      return new WorkerJvm(name, builder.start());
    } catch (IOException e) {
      throw new UncheckedIOException("cannot start worker JVM " + name, e);
    }
  }

  /** Starts a worker with no extra options or environment. */
  static WorkerJvm start(String name, String... args) {
    return start(name, List.of(), Map.of(), List.of(args));
  }

  /**
   * Waits for the first line that matches {@code wanted} (looking at every line so far too).
   *
   * @return the line, or empty if the worker ended or {@code timeout} passed first
   */
  Optional<String> awaitLine(Predicate<String> wanted, Duration timeout) throws InterruptedException {
    long deadline = System.nanoTime() + timeout.toNanos();
    synchronized (lines) {
      int checked = 0;
      while (true) {
        for (; checked < lines.size(); checked++) {
          if (wanted.test(lines.get(checked))) return Optional.of(lines.get(checked));
        }
        long left = deadline - System.nanoTime();
        if (ended || left <= 0) return Optional.empty();
        TimeUnit.NANOSECONDS.timedWait(lines, left);
      }
    }
  }

  /** Waits for the worker's {@code READY} line; fails with the worker's output if it does not come. */
  String awaitReady() throws InterruptedException {
    return awaitLine(line -> line.startsWith("READY"), FaultMode.PATIENCE)
        .orElseThrow(() -> new AssertionError("worker " + name + " did not print READY; output:\n" + output()));
  }

  /** Kills the worker with SIGKILL and waits until it is gone. */
  void kill() {
    process.destroyForcibly();
    awaitExit(FaultMode.PATIENCE);
  }

  /** Asks the worker to stop with SIGTERM (its shutdown hooks run) and waits until it is gone. */
  void terminate() {
    process.destroy();
    awaitExit(FaultMode.PATIENCE);
  }

  /** Waits for the worker to end; returns its exit code. */
  int awaitExit(Duration timeout) {
    try {
      if (!process.waitFor(timeout.toMillis(), TimeUnit.MILLISECONDS)) {
        throw new AssertionError("worker " + name + " did not end within " + timeout + "; output:\n" + output());
      }
      pump.join(timeout.toMillis());
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
      throw new AssertionError("interrupted while waiting for worker " + name, e);
    }
    return process.exitValue();
  }

  /** Everything the worker printed so far. */
  String output() {
    synchronized (lines) {
      return String.join("\n", lines);
    }
  }

  /** How many lines printed so far contain {@code text}. */
  long linesContaining(String text) {
    synchronized (lines) {
      return lines.stream().filter(line -> line.contains(text)).count();
    }
  }

  @Override
  public void close() {
    if (process.isAlive()) {
      process.destroyForcibly();
      try {
        process.waitFor(FaultMode.PATIENCE.toSeconds(), TimeUnit.SECONDS);
      } catch (InterruptedException e) {
        Thread.currentThread().interrupt();
      }
    }
  }

  private void readOutput() {
    try (BufferedReader reader = new BufferedReader(new InputStreamReader(process.getInputStream(), StandardCharsets.UTF_8))) {
      for (String line = reader.readLine(); line != null; line = reader.readLine()) {
        synchronized (lines) {
          lines.add(line);
          lines.notifyAll();
        }
      }
    } catch (IOException e) {
      // the process was destroyed: its output ends here
    } finally {
      synchronized (lines) {
        ended = true;
        lines.notifyAll();
      }
    }
  }

  @Override
  public String toString() {
    return "WorkerJvm[" + name + ", pid " + process.pid() + "]";
  }
}

package dev.prime.conformance;

import java.io.ByteArrayOutputStream;
import java.io.OutputStream;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.time.Duration;
import java.util.List;
import java.util.Optional;
import java.util.function.Predicate;
import java.util.regex.Matcher;
import java.util.regex.Pattern;

/**
 * Copies what is written to {@link System#err} (where the tests' slf4j-simple binding logs) into a
 * buffer while open, still passing it on. Tests filter its lines by names of their own, since other
 * threads may log at the same time.
 */
public final class CapturedStderr implements AutoCloseable {
  /** A rate-limited log's summary line: "...: 37 more in the last 10 s; the last: ...". */
  private static final Pattern SUMMARY = Pattern.compile("(\\d+) more in the last");

  private final PrintStream original = System.err;
  private final ByteArrayOutputStream copy = new ByteArrayOutputStream();

  /** Starts capturing. */
  public CapturedStderr() {
    OutputStream tee =
        new OutputStream() {
          @Override
          public void write(int b) {
            synchronized (copy) {
              copy.write(b);
              copy.notifyAll();
            }
            original.write(b);
          }

          @Override
          public void write(byte[] bytes, int offset, int length) {
            synchronized (copy) {
              copy.write(bytes, offset, length);
              copy.notifyAll();
            }
            original.write(bytes, offset, length);
          }
        };
    System.setErr(new PrintStream(tee, true, StandardCharsets.UTF_8));
  }

  /** {@return the lines captured so far} */
  public List<String> lines() {
    synchronized (copy) {
      return copy.toString(StandardCharsets.UTF_8).lines().toList();
    }
  }

  /**
   * Waits until a captured line matches {@code wanted}, woken by each write rather than looking
   * again at intervals, at most {@code timeout}.
   *
   * @param wanted what the line must satisfy
   * @param timeout the longest wait
   * @return the first matching line, or empty if none came within {@code timeout}
   * @throws InterruptedException if the waiting thread is interrupted
   */
  public Optional<String> awaitLine(Predicate<String> wanted, Duration timeout)
      throws InterruptedException {
    long deadline = System.nanoTime() + timeout.toNanos();
    synchronized (copy) {
      while (true) {
        Optional<String> line =
            copy.toString(StandardCharsets.UTF_8).lines().filter(wanted).findFirst();
        long left = deadline - System.nanoTime();
        if (line.isPresent() || left <= 0) {
          return line;
        }
        copy.wait(Math.max(1, left / 1_000_000));
      }
    }
  }

  /**
   * {@return how many events a rate-limited log's summary line counts ("37 more in the last 10 s":
   * 37), 0 for any other line}
   *
   * @param line a captured line
   */
  public static long summarised(String line) {
    Matcher count = SUMMARY.matcher(line);
    return count.find() ? Long.parseLong(count.group(1)) : 0;
  }

  /** Restores the original stream. */
  @Override
  public void close() {
    System.err.flush();
    System.setErr(original);
  }
}

package dev.prime.conformance;

import java.io.ByteArrayOutputStream;
import java.io.OutputStream;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.util.List;
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
            }
            original.write(b);
          }

          @Override
          public void write(byte[] bytes, int offset, int length) {
            synchronized (copy) {
              copy.write(bytes, offset, length);
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

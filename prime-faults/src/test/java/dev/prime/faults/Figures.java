package dev.prime.faults;

import java.io.IOException;
import java.io.UncheckedIOException;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.nio.file.StandardOpenOption;
import java.time.Duration;
import java.util.Locale;

/**
 * The one summary line each fault test prints with its figures, e.g. {@code kill-worker SIGKILL
 * run 1/2: 2000 sent, 0 lost, 0 duplicated, 0 reordered, recovered in 0.41 s}. Lines go to
 * standard output and to {@code target/fault-figures.txt} (started afresh by each run), so a
 * run's figures can be quoted as they are.
 */
final class Figures {
  private static final Path FILE = Path.of("target", "fault-figures.txt");
  private static boolean started; // guarded by Figures.class: the first line of a run starts a new file

  private Figures() {}

  /** Prints {@code line} (prefixed with the mode) and appends it to the figures file. */
  static synchronized void report(String line) {
    String full = "[faults " + FaultMode.current().name().toLowerCase(Locale.ROOT) + "] " + line;
    System.out.println(full);
    try {
      Files.createDirectories(FILE.getParent());
      Files.writeString(FILE, full + System.lineSeparator(), StandardCharsets.UTF_8, StandardOpenOption.CREATE,
          started ? StandardOpenOption.APPEND : StandardOpenOption.TRUNCATE_EXISTING);
      started = true;
    } catch (IOException e) {
      throw new UncheckedIOException("cannot write " + FILE.toAbsolutePath(), e);
    }
  }

  /** {@code 0.41 s}. */
  static String seconds(Duration duration) {
    return String.format(Locale.ROOT, "%.2f s", duration.toNanos() / 1e9);
  }

  /** {@code 0.41 s}, from a {@link System#nanoTime()} difference. */
  static String seconds(long nanos) {
    return seconds(Duration.ofNanos(nanos));
  }
}

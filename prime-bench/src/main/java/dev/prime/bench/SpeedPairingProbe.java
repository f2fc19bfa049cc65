package dev.prime.bench;

import java.util.ArrayList;
import java.util.List;
import java.util.Locale;
import java.util.function.LongSupplier;

/**
 * Measures the machine's core-to-core round trip and a Prime row in alternating windows of one
 * JVM, to tell whether the row's slow mode follows the machine's slow speed (both slow in the same
 * windows) or has a cause of its own (the row slow while the round trip is fast). The JMH runs
 * measure them minutes apart, so they cannot tell. The row is the synchronous Prime-sources row
 * ({@code row}, {@link SyncSourceBenchmark}) or the asynchronous hand-off ({@code handoff}, {@link
 * AsyncHandOffBenchmark#primeSource}, time per value of batches of {@value
 * AsyncHandOffBenchmark#BATCH}).
 *
 * <p>Each window runs one of the two alone: the round trip's echo thread is started for its window
 * and stopped (joined) before the row's, and the row's service thread parks within 200 µs of the
 * last value, so the two never share the cores. Not a JMH benchmark: it prints each window and a
 * two-by-two count of slow and fast windows.
 *
 * <pre>{@code
 * java -cp prime-bench/target/benchmarks.jar dev.prime.bench.SpeedPairingProbe [payload] [windows] [windowMillis] [warmUpSeconds] [row|handoff]
 * }</pre>
 *
 * <p>Defaults: 100 B, 200 windows of each, 100 ms per window, after 5 s of warm-up (windows of
 * both, not printed), the synchronous row.
 */
public final class SpeedPairingProbe {
  /** A round trip slower than this counts as the machine's slow speed (the two groups: ~120, ~440 ns). */
  private static final double SLOW_ROUND_TRIP_NANOS = 280;

  /** A row transmission slower than this counts as the row's slow mode (groups: ~300, ~1,200 ns). */
  static final double SLOW_ROW_NANOS = 700;

  /** A hand-off slower than this per value counts as its slow mode (fork means: 25–45, 60–100 ns). */
  static final double SLOW_HANDOFF_NANOS = 52;

  private SpeedPairingProbe() {}

  /**
   * A Prime row measured in windows: {@code step} moves {@code valuesPerStep} values through it,
   * and the clock is read every {@code stepsPerClockRead} steps (a read costs tens of ns, a
   * synchronous transmission a few hundred).
   */
  private static final class Row implements AutoCloseable {
    private final LongSupplier step;
    private final int valuesPerStep;
    private final int stepsPerClockRead;
    private final Runnable close;
    private long sink;

    Row(LongSupplier step, int valuesPerStep, int stepsPerClockRead, Runnable close) {
      this.step = step;
      this.valuesPerStep = valuesPerStep;
      this.stepsPerClockRead = stepsPerClockRead;
      this.close = close;
    }

    /** The mean time of one value over a window of about {@code nanos}. */
    double window(long nanos) {
      long start = System.nanoTime();
      long values = 0;
      long now;
      do {
        for (int i = 0; i < stepsPerClockRead; i++) {
          sink += step.getAsLong();
        }
        values += (long) stepsPerClockRead * valuesPerStep;
        now = System.nanoTime();
      } while (now - start < nanos);
      return (double) (now - start) / values;
    }

    @Override
    public void close() {
      close.run();
      if (sink == 42) {
        System.out.print(""); // keeps the outputs alive
      }
    }
  }

  /**
   * Runs the probe.
   *
   * @param args payload bytes, windows of each, milliseconds per window, seconds of warm-up, and
   *     {@code row} or {@code handoff} (all optional)
   * @throws InterruptedException if interrupted while stopping the echo thread
   */
  public static void main(String[] args) throws InterruptedException {
    int payload = (int) argument(args, 0, 100, 0, 1 << 20);
    int windows = (int) argument(args, 1, 200, 1, 100_000);
    long windowNanos = argument(args, 2, 100, 1, 60_000) * 1_000_000L;
    long warmUpNanos = argument(args, 3, 5, 0, 3_600) * 1_000_000_000L;
    String which = args.length > 4 ? args[4] : "row";
    if (!(which.equals("row") || which.equals("handoff"))) {
      throw new IllegalArgumentException("the fifth argument is '" + which + "': " + USAGE);
    }
    Shape shape = new Shape();
    shape.length = 4;
    shape.payload = payload;
    shape.scenario = "monomorphic";
    double slow = which.equals("row") ? SLOW_ROW_NANOS : SLOW_HANDOFF_NANOS;
    try (Row row = which.equals("row") ? synchronousRow(shape) : handOff(shape)) {
      long warmUpEnd = System.nanoTime() + warmUpNanos;
      while (System.nanoTime() - warmUpEnd < 0) {
        roundTripWindow(windowNanos);
        row.window(windowNanos);
      }
      List<double[]> pairs = new ArrayList<>();
      for (int i = 0; i < windows; i++) {
        double roundTrip = roundTripWindow(windowNanos);
        double value = row.window(windowNanos);
        pairs.add(new double[] {roundTrip, value});
        System.out.printf(
            Locale.ROOT, "window %d: round trip %.0f ns, %s %.0f ns%n", i, roundTrip, which, value);
      }
      System.out.println(summary(pairs, which, slow));
    }
  }

  private static final String USAGE =
      "give payload (0 to 1048576 bytes), windows (1 to 100000), windowMillis (1 to 60000),"
          + " warmUpSeconds (0 to 3600) and row or handoff, e.g. 100 200 100 5 row";

  /** Argument {@code index} as a whole number from {@code min} to {@code max}, or {@code absent}. */
  private static long argument(String[] args, int index, long absent, long min, long max) {
    if (args.length <= index) {
      return absent;
    }
    try {
      long value = Long.parseLong(args[index].trim());
      if (value >= min && value <= max) {
        return value;
      }
    } catch (NumberFormatException e) {
      // refused below, with what to give
    }
    throw new IllegalArgumentException(
        "argument " + (index + 1) + " is '" + args[index] + "': " + USAGE);
  }

  /** The synchronous Prime-sources row: one value there and its output back. */
  private static Row synchronousRow(Shape shape) {
    SyncChainBenchmark.Input input = new SyncChainBenchmark.Input();
    input.build(shape);
    SyncSourceBenchmark.Collected collected = new SyncSourceBenchmark.Collected();
    collected.build(shape);
    SyncSourceBenchmark transmissions = new SyncSourceBenchmark();
    return new Row(() -> transmissions.primeSource(input, collected), 1, 64, collected::close);
  }

  /** The asynchronous hand-off: batches published to a source, the linked chain on its thread. */
  private static Row handOff(Shape shape) {
    AsyncHandOffBenchmark.Batch batch = new AsyncHandOffBenchmark.Batch();
    batch.build(shape);
    AsyncHandOffBenchmark.PrimeSource source = new AsyncHandOffBenchmark.PrimeSource();
    source.build(shape);
    AsyncHandOffBenchmark batches = new AsyncHandOffBenchmark();
    return new Row(
        () -> batches.primeSource(batch, source), AsyncHandOffBenchmark.BATCH, 1, source::close);
  }

  /** The mean round trip over one window, with an echo thread of its own. */
  private static double roundTripWindow(long windowNanos) throws InterruptedException {
    CoreRoundTripBenchmark.Echo echo = new CoreRoundTripBenchmark.Echo();
    echo.start();
    try {
      echo.roundTrip(); // the echo thread is running
      long start = System.nanoTime();
      long trips = 0;
      long now;
      do {
        for (int i = 0; i < 256; i++) {
          echo.roundTrip();
        }
        trips += 256;
        now = System.nanoTime();
      } while (now - start < windowNanos);
      return (double) (now - start) / trips;
    } finally {
      echo.stop();
      if (echo.echoing()) {
        throw new IllegalStateException("the echo thread did not stop within 10 s");
      }
    }
  }

  /**
   * How many windows paired each speed of the round trip with each mode of the row.
   *
   * @param pairs per window, the mean round trip and the row's mean time per value, in ns
   * @param row the row's name
   * @param slowRowNanos above this the row counts as slow
   * @return one line of counts
   */
  static String summary(List<double[]> pairs, String row, double slowRowNanos) {
    int[][] counts = new int[2][2];
    for (double[] pair : pairs) {
      counts[pair[0] > SLOW_ROUND_TRIP_NANOS ? 1 : 0][pair[1] > slowRowNanos ? 1 : 0]++;
    }
    return String.format(
        Locale.ROOT,
        "%d windows; round trip fast (<= %.0f ns): %s fast %d, %s slow (> %.0f ns) %d;"
            + " round trip slow: %s fast %d, %s slow %d",
        pairs.size(),
        SLOW_ROUND_TRIP_NANOS,
        row,
        counts[0][0],
        row,
        slowRowNanos,
        counts[0][1],
        row,
        counts[1][0],
        row,
        counts[1][1]);
  }
}

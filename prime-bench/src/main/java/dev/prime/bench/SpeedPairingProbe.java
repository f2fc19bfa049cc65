package dev.prime.bench;

import java.util.ArrayList;
import java.util.List;
import java.util.Locale;

/**
 * Measures the machine's core-to-core round trip and the synchronous Prime-sources row in
 * alternating windows of one JVM, to tell whether the row's slow mode follows the machine's slow
 * speed (both slow in the same windows) or has a cause of its own (the row slow while the round
 * trip is fast). The JMH runs measure the two minutes apart, so they cannot tell.
 *
 * <p>Each window runs one of the two alone: the round trip's echo thread is started for its window
 * and stopped (joined) before the row's, and the row's service thread parks within 200 µs of the
 * last value, so the two never share the cores. Not a JMH benchmark: it prints each window and a
 * two-by-two count of slow and fast windows.
 *
 * <pre>{@code
 * java -cp prime-bench/target/benchmarks.jar dev.prime.bench.SpeedPairingProbe [payload] [windows] [windowMillis] [warmUpSeconds]
 * }</pre>
 *
 * <p>Defaults: 100 B, 200 windows of each, 100 ms per window, after 5 s of warm-up (windows of both, not printed).
 */
public final class SpeedPairingProbe {
  /** A round trip slower than this counts as the machine's slow speed (the two groups: ~120, ~440 ns). */
  private static final double SLOW_ROUND_TRIP_NANOS = 280;

  /** A row transmission slower than this counts as the row's slow mode (groups: ~300, ~1,200 ns). */
  private static final double SLOW_ROW_NANOS = 700;

  private SpeedPairingProbe() {}

  /**
   * Runs the probe.
   *
   * @param args payload bytes, windows of each, milliseconds per window, seconds of warm-up (all
   *     optional)
   * @throws InterruptedException if interrupted while stopping the echo thread
   */
  public static void main(String[] args) throws InterruptedException {
    int payload = args.length > 0 ? Integer.parseInt(args[0]) : 100;
    int windows = args.length > 1 ? Integer.parseInt(args[1]) : 200;
    long windowNanos = (args.length > 2 ? Long.parseLong(args[2]) : 100) * 1_000_000L;
    long warmUpNanos = (args.length > 3 ? Long.parseLong(args[3]) : 5) * 1_000_000_000L;
    if (payload < 0 || windows < 1 || windowNanos < 1_000_000L || warmUpNanos < 0) {
      throw new IllegalArgumentException(
          "give payload >= 0, windows >= 1, windowMillis >= 1 and warmUpSeconds >= 0, e.g. 100 200 100 5");
    }
    Shape shape = new Shape();
    shape.length = 4;
    shape.payload = payload;
    shape.scenario = "monomorphic";
    SyncChainBenchmark.Input input = new SyncChainBenchmark.Input();
    input.build(shape);
    SyncSourceBenchmark.Collected row = new SyncSourceBenchmark.Collected();
    row.build(shape);
    try {
      long warmUpEnd = System.nanoTime() + warmUpNanos;
      while (System.nanoTime() - warmUpEnd < 0) {
        roundTripWindow(windowNanos);
        rowWindow(row, input, windowNanos);
      }
      List<double[]> pairs = new ArrayList<>();
      for (int i = 0; i < windows; i++) {
        double roundTrip = roundTripWindow(windowNanos);
        double transmission = rowWindow(row, input, windowNanos);
        pairs.add(new double[] {roundTrip, transmission});
        System.out.printf(Locale.ROOT, "window %d: round trip %.0f ns, row %.0f ns%n", i, roundTrip, transmission);
      }
      System.out.println(summary(pairs));
    } finally {
      row.close();
    }
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

  /** The mean transmission of the synchronous row over one window. */
  private static double rowWindow(
      SyncSourceBenchmark.Collected row, SyncChainBenchmark.Input input, long windowNanos) {
    SyncSourceBenchmark transmissions = new SyncSourceBenchmark();
    long start = System.nanoTime();
    long count = 0;
    long sink = 0;
    long now;
    do {
      for (int i = 0; i < 64; i++) {
        sink += transmissions.primeSource(input, row);
      }
      count += 64;
      now = System.nanoTime();
    } while (now - start < windowNanos);
    if (sink == 42) {
      System.out.print(""); // keeps the outputs alive
    }
    return (double) (now - start) / count;
  }

  /**
   * How many windows paired each speed of the round trip with each mode of the row.
   *
   * @param pairs per window, the mean round trip and the mean row transmission, in ns
   * @return one line of counts
   */
  static String summary(List<double[]> pairs) {
    int[][] counts = new int[2][2];
    for (double[] pair : pairs) {
      counts[pair[0] > SLOW_ROUND_TRIP_NANOS ? 1 : 0][pair[1] > SLOW_ROW_NANOS ? 1 : 0]++;
    }
    return String.format(
        Locale.ROOT,
        "%d windows; round trip fast (<= %.0f ns): row fast %d, row slow (> %.0f ns) %d;"
            + " round trip slow: row fast %d, row slow %d",
        pairs.size(),
        SLOW_ROUND_TRIP_NANOS,
        counts[0][0],
        SLOW_ROW_NANOS,
        counts[0][1],
        counts[1][0],
        counts[1][1]);
  }
}

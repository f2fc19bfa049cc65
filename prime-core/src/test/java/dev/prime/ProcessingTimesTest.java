package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.util.Arrays;
import org.junit.jupiter.api.Test;

/** The histogram's fixed buckets and the percentiles read from them. */
class ProcessingTimesTest {
  private static final long[] BOUNDS = ProcessingTimes.upperBoundsNanos();

  @Test
  void boundsAscendFromTwoHundredFiftySixNanosInStepsOfAtMostAQuarter() {
    assertEquals(256, BOUNDS[0]);
    assertEquals(320, BOUNDS[1]);
    assertEquals(512, BOUNDS[4]);
    assertEquals(1L << 37, BOUNDS[BOUNDS.length - 2]);
    assertEquals(Long.MAX_VALUE, BOUNDS[BOUNDS.length - 1]);
    for (int i = 1; i < BOUNDS.length - 1; i++) {
      assertTrue(BOUNDS[i] > BOUNDS[i - 1]);
      assertTrue(BOUNDS[i] - BOUNDS[i - 1] <= BOUNDS[i - 1] / 4, "step at " + i);
    }
  }

  @Test
  void everyTimeFallsInTheFirstBucketWhoseBoundHoldsIt() {
    long[] probes = {0, 1, 255, 256, 257, 319, 320, 321, 511, 512, 513, 1_000, 999_999, 1L << 36,
        (1L << 37) - 1, 1L << 37, (1L << 37) + 1, Long.MAX_VALUE, -5};
    for (long t : probes) {
      int bucket = ProcessingTimes.bucket(t);
      long clamped = Math.max(0, t);
      assertTrue(clamped <= BOUNDS[bucket], t + " above its bucket's bound " + BOUNDS[bucket]);
      assertTrue(bucket == 0 || clamped > BOUNDS[bucket - 1], t + " fits an earlier bucket");
    }
    for (int i = 0; i < BOUNDS.length - 1; i++) { // every bound, and one past it
      assertEquals(i, ProcessingTimes.bucket(BOUNDS[i]), "bound " + BOUNDS[i]);
      assertEquals(i + 1, ProcessingTimes.bucket(BOUNDS[i] + 1), "past " + BOUNDS[i]);
    }
  }

  @Test
  void percentilesAreTheUpperBoundOfTheirBucketNeverAboveTheMax() {
    long[] counts = new long[ProcessingTimes.bucketCount()];
    long total = 0;
    long[] times = new long[100];
    for (int i = 0; i < 100; i++) {
      times[i] = 1_000L * (i + 1); // 1 µs .. 100 µs
      counts[ProcessingTimes.bucket(times[i])]++;
      total += times[i];
    }
    ProcessingTimes h = new ProcessingTimes(counts, total, 100_000);
    assertEquals(100, h.count());
    assertEquals(total / 100.0, h.meanNanos());
    for (double q : new double[] {0.01, 0.5, 0.9, 0.99, 1.0}) {
      long exact = times[(int) Math.ceil(q * 100) - 1];
      long estimate = h.percentileNanos(q);
      assertTrue(estimate >= exact, q + ": " + estimate + " < " + exact);
      assertTrue(estimate <= exact + exact / 4, q + ": " + estimate + " more than 25% over " + exact);
    }
    assertEquals(100_000, h.percentileNanos(1.0), "the top is the max, not the bucket's bound");
    assertEquals(0, ProcessingTimes.EMPTY.percentileNanos(0.99));
    assertEquals(0, ProcessingTimes.EMPTY.meanNanos());
    IllegalArgumentException e =
        assertThrows(IllegalArgumentException.class, () -> h.percentileNanos(99));
    assertTrue(e.getMessage().contains("between 0 and 1"), e.getMessage());
    assertThrows(IllegalArgumentException.class, () -> h.percentileNanos(Double.NaN));
    long[] copy = h.bucketCounts();
    copy[0] = 1_000;
    assertEquals(100, Arrays.stream(h.bucketCounts()).sum(), "a copy: the histogram is immutable");
  }
}

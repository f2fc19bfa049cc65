package dev.prime;

import java.util.Arrays;

/**
 * An immutable histogram of how long a service took per value, in nanoseconds: the count, the
 * total, the largest, and counts in fixed log-scale buckets from which percentiles are estimated.
 *
 * <p>Buckets. The bounds are the same for every service and every media ({@link
 * #upperBoundsNanos()}): the first bucket holds times up to 256 ns; from there each power of two
 * is split into four buckets (upper bounds 320, 384, 448, 512, 640, ... ns, a step of at most 25 %)
 * up to 2<sup>37</sup> ns (about 137 s); the last bucket holds everything longer. A {@linkplain
 * #percentileNanos(double) percentile} is the upper bound of the bucket it falls in (at most the
 * {@linkplain #maxNanos() largest time}), so it is never under the true value and at most 25 %
 * over it (above 256 ns).
 */
public final class ProcessingTimes {
  private static final int FIRST_POWER = 8; // the first bucket: up to 2^8 ns
  private static final int LAST_POWER = 37; // the last bounded bucket ends at 2^37 ns
  private static final int SPLITS = 4; // buckets per power of two
  private static final long[] UPPER_BOUNDS = upperBounds();

  /** The histogram of a service that has processed nothing. */
  static final ProcessingTimes EMPTY = new ProcessingTimes(new long[UPPER_BOUNDS.length], 0, 0);

  private final long[] counts;
  private final long count;
  private final long totalNanos;
  private final long maxNanos;

  ProcessingTimes(long[] counts, long totalNanos, long maxNanos) {
    this.counts = counts;
    long sum = 0;
    for (long c : counts) {
      sum += c;
    }
    this.count = sum;
    this.totalNanos = totalNanos;
    this.maxNanos = maxNanos;
  }

  /** {@return how many buckets every histogram has} */
  static int bucketCount() {
    return UPPER_BOUNDS.length;
  }

  /**
   * The bucket a time falls in: a few shifts, no loop (it runs once per processed value).
   *
   * @param nanos a time, negative read as 0
   * @return the bucket's index
   */
  static int bucket(long nanos) {
    if (nanos <= 1L << FIRST_POWER) {
      return 0;
    }
    long n = nanos - 1; // an upper bound belongs to its own bucket
    int power = 63 - Long.numberOfLeadingZeros(n); // 2^power <= n < 2^(power+1)
    if (power >= LAST_POWER) {
      return UPPER_BOUNDS.length - 1;
    }
    int split = (int) (n >>> (power - 2)) & (SPLITS - 1);
    return 1 + (power - FIRST_POWER) * SPLITS + split;
  }

  private static long[] upperBounds() {
    int bounded = 1 + (LAST_POWER - FIRST_POWER) * SPLITS;
    long[] bounds = new long[bounded + 1];
    bounds[0] = 1L << FIRST_POWER;
    int i = 1;
    for (int power = FIRST_POWER; power < LAST_POWER; power++) {
      for (int split = 1; split <= SPLITS; split++) {
        bounds[i++] = (1L << power) + ((1L << power) / SPLITS) * split;
      }
    }
    bounds[bounded] = Long.MAX_VALUE;
    return bounds;
  }

  /** {@return how many values were timed: the sum of the bucket counts} */
  public long count() {
    return count;
  }

  /** {@return the sum of the times, in nanoseconds} */
  public long totalNanos() {
    return totalNanos;
  }

  /** {@return the longest time, in nanoseconds; 0 if nothing was timed} */
  public long maxNanos() {
    return maxNanos;
  }

  /** {@return the mean time in nanoseconds, 0 if nothing was timed} */
  public double meanNanos() {
    return count == 0 ? 0 : (double) totalNanos / count;
  }

  /**
   * {@return the buckets' upper bounds in nanoseconds, ascending, the same for every histogram;
   * the last is {@link Long#MAX_VALUE}} A time {@code t} is counted in the first bucket whose
   * bound is {@code >= t}.
   */
  public static long[] upperBoundsNanos() {
    return UPPER_BOUNDS.clone();
  }

  /** {@return how many times fell in each bucket, in the order of {@link #upperBoundsNanos()}} */
  public long[] bucketCounts() {
    return counts.clone();
  }

  /**
   * Estimates a percentile from the buckets: the upper bound of the bucket in which the {@code
   * quantile}'s share of the values is reached, at most {@link #maxNanos()}.
   *
   * @param quantile between 0 and 1 (0.5 for the median, 0.99 for the 99th percentile)
   * @return the estimate in nanoseconds; 0 if nothing was timed
   * @throws IllegalArgumentException if {@code quantile} is not between 0 and 1
   */
  public long percentileNanos(double quantile) {
    if (!(quantile >= 0 && quantile <= 1)) {
      throw new IllegalArgumentException(
          "quantile must be between 0 and 1 (0.99 for the 99th percentile), was " + quantile);
    }
    if (count == 0) {
      return 0;
    }
    long rank = Math.max(1, (long) Math.ceil(quantile * count));
    long seen = 0;
    for (int i = 0; i < counts.length; i++) {
      seen += counts[i];
      if (seen >= rank) {
        return Math.min(UPPER_BOUNDS[i], maxNanos);
      }
    }
    return maxNanos;
  }

  @Override
  public boolean equals(Object o) {
    return o instanceof ProcessingTimes other
        && totalNanos == other.totalNanos
        && maxNanos == other.maxNanos
        && Arrays.equals(counts, other.counts);
  }

  @Override
  public int hashCode() {
    return Arrays.hashCode(counts) * 31 + Long.hashCode(totalNanos);
  }

  @Override
  public String toString() {
    return "ProcessingTimes[count=" + count + ", meanNanos=" + (long) meanNanos()
        + ", p50=" + percentileNanos(0.5) + ", p99=" + percentileNanos(0.99)
        + ", maxNanos=" + maxNanos + "]";
  }
}

package dev.prime;

import java.time.Duration;
import java.util.Objects;

/**
 * How a core records what its event sources publish and its chains made of a block return (only
 * those: filters, flat-maps, listeners, templates and other services are not recorded; see {@link
 * Recording}):
 * the size of the ring kept per recorded name and how long {@link Recording#get(String)} waits for
 * a first value. Immutable. Give it to {@link CoreConfig.Builder#recording(RecordingOptions)};
 * without it a core records nothing and pays nothing.
 *
 * <pre>{@code
 * CoreConfig.builder().recording(RecordingOptions.ring(10_000)).build()
 * }</pre>
 */
public final class RecordingOptions {

  /** Default number of values kept per recorded name. */
  public static final int DEFAULT_CAPACITY = 10_000;

  /** Default time {@link Recording#get(String)} waits for a first value. */
  public static final Duration DEFAULT_GET_TIMEOUT = Duration.ofSeconds(5);

  private final int capacity;
  private final Duration getTimeout;

  private RecordingOptions(int capacity, Duration getTimeout) {
    this.capacity = capacity;
    this.getTimeout = getTimeout;
  }

  /** {@return recording with the default ring of {@value #DEFAULT_CAPACITY} values per name} */
  public static RecordingOptions defaults() {
    return ring(DEFAULT_CAPACITY);
  }

  /**
   * Recording that keeps the latest {@code capacity} values of each recorded name; older ones
   * fall out of the ring and are counted ({@link Recording#dropped(String)}).
   *
   * @param capacity values kept per name, 1 to 100,000,000
   * @return the options, with the default get timeout
   * @throws IllegalArgumentException if {@code capacity} is out of range
   */
  public static RecordingOptions ring(int capacity) {
    if (capacity < 1 || capacity > 100_000_000) {
      throw new IllegalArgumentException(
          "a recording ring holds 1 to 100,000,000 values per name, was " + capacity);
    }
    return new RecordingOptions(capacity, DEFAULT_GET_TIMEOUT);
  }

  /**
   * These options with another wait for {@link Recording#get(String)}.
   *
   * @param timeout how long {@code get} waits for a first value; zero or positive
   * @return new options
   */
  public RecordingOptions withGetTimeout(Duration timeout) {
    Objects.requireNonNull(timeout, "getTimeout must not be null");
    if (timeout.isNegative()) {
      throw new IllegalArgumentException("getTimeout must be zero or positive, was " + timeout);
    }
    return new RecordingOptions(capacity, timeout);
  }

  /** {@return how many values are kept per recorded name} */
  public int capacity() {
    return capacity;
  }

  /** {@return how long {@link Recording#get(String)} waits for a first value} */
  public Duration getTimeout() {
    return getTimeout;
  }

  @Override
  public String toString() {
    return "RecordingOptions[capacity=" + capacity + ", getTimeout=" + getTimeout + "]";
  }
}

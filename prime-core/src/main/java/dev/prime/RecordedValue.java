package dev.prime;

import java.time.Instant;
import java.util.Objects;

/**
 * One recorded value with its time stamps: what a source published or a chain returned.
 *
 * @param service the recorded name (a source's or chain's name in the topology)
 * @param pseudoname the readable name given at creation, or {@code null} if none was given
 * @param sequence the value's number under its name in the recording process: 0, 1, 2, ...
 *     without gaps (values that fell out of the ring keep their numbers)
 * @param wallTime by the wall clock, when the chain's block returned the value or the source's
 *     publish of it began (comparable across processes as far as their clocks agree)
 * @param monotonicNanos the same moment by {@link System#nanoTime()} of the recording process
 *     (meaningful only against other stamps of the same process)
 * @param value the value, as published or returned (not a copy)
 * @param <T> the value's type
 */
public record RecordedValue<T>(
    String service,
    String pseudoname,
    long sequence,
    Instant wallTime,
    long monotonicNanos,
    T value) {

  /**
   * Checks the components.
   *
   * @param service the recorded name; not {@code null}
   * @param pseudoname the readable name, or {@code null}
   * @param sequence the value's number under its name; not negative
   * @param wallTime the wall-clock stamp; not {@code null}
   * @param monotonicNanos the monotonic stamp
   * @param value the value; not {@code null}
   * @throws NullPointerException if {@code service}, {@code wallTime} or {@code value} is null
   * @throws IllegalArgumentException if {@code sequence} is negative
   */
  public RecordedValue {
    Objects.requireNonNull(service, "service");
    Objects.requireNonNull(wallTime, "wallTime");
    Objects.requireNonNull(value, "value");
    if (sequence < 0) {
      throw new IllegalArgumentException("sequence must not be negative, was " + sequence);
    }
  }

  /** {@return the pseudoname if one was given, otherwise the service name} */
  public String label() {
    return pseudoname != null ? pseudoname : service;
  }
}

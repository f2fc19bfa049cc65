package dev.prime.mcap;

import dev.prime.PrimeClock;
import java.util.Objects;
import java.util.Optional;

/**
 * How fast a {@link McapReplay} feeds its values: {@link #asFastAsPossible()} (the default: each
 * value as soon as the one before was fed), or {@link #recordedSpeed()}, where each value is fed
 * when as much time has passed since the first one as passed between their log times in the file.
 */
public final class ReplayOptions {
  private static final ReplayOptions FAST = new ReplayOptions(null);

  private final PrimeClock clock;

  private ReplayOptions(PrimeClock clock) {
    this.clock = clock;
  }

  /** {@return options that feed every value as soon as the one before it was fed} */
  public static ReplayOptions asFastAsPossible() {
    return FAST;
  }

  /** {@return options that keep the recorded intervals between values, on the system's clock} */
  public static ReplayOptions recordedSpeed() {
    return recordedSpeed(PrimeClock.system());
  }

  /**
   * Keeps the recorded intervals between values, measured and waited on {@code clock}.
   *
   * @param clock the clock (a test's own, whose sleep only moves its time, makes the replay
   *     instant)
   * @return the options
   */
  public static ReplayOptions recordedSpeed(PrimeClock clock) {
    return new ReplayOptions(Objects.requireNonNull(clock, "clock must not be null"));
  }

  /** {@return the clock a replay at recorded speed paces itself by; empty: as fast as possible} */
  public Optional<PrimeClock> pacing() {
    return Optional.ofNullable(clock);
  }

  @Override
  public String toString() {
    return clock == null ? "ReplayOptions[as fast as possible]" : "ReplayOptions[recorded speed]";
  }
}

package dev.prime;

import java.time.Instant;

/**
 * The time a core runs on: what its timers ({@link PrimeCore#timer}) and samplers ({@link
 * Source#sample}) measure and wait by. Set it with {@link CoreConfig.Builder#clock(PrimeClock)};
 * the default is {@link #system()}. Tests and simulations use a {@link VirtualClock}, whose time
 * moves only when the test advances it, so a controller driven by timers runs as fast as the
 * machine allows and gives the same ticks every run.
 *
 * <p>Implementations are thread-safe.
 */
public interface PrimeClock {

  /**
   * A monotonic reading in nanoseconds, for measuring elapsed time (like {@link
   * System#nanoTime()}: only differences between readings mean something).
   *
   * @return the current reading
   */
  long nanoTime();

  /**
   * Waits until {@code nanos} nanoseconds of this clock's time have passed (returns at once for
   * zero or less).
   *
   * @param nanos how long to wait, in this clock's nanoseconds
   * @throws InterruptedException if the thread is interrupted while it waits (the interrupt flag
   *     is cleared, as by {@link Thread#sleep(long)})
   */
  void sleepNanos(long nanos) throws InterruptedException;

  /**
   * Waits until this clock's {@link #nanoTime()} reaches {@code deadline} (returns at once if it
   * has). Unlike {@link #sleepNanos(long)} it does not oversleep when the clock moves between
   * reading the time and starting to wait, which matters for a {@link VirtualClock} advanced by
   * another thread: timers wait with it. The default sleeps for the difference.
   *
   * @param deadline a reading of {@link #nanoTime()}
   * @throws InterruptedException if the thread is interrupted while it waits
   */
  default void sleepUntil(long deadline) throws InterruptedException {
    sleepNanos(deadline - nanoTime());
  }

  /**
   * The current wall-clock time of this clock, for time stamps.
   *
   * @return now
   */
  Instant now();

  /**
   * The real time of the machine: {@link System#nanoTime()}, {@link Thread#sleep} and {@link
   * Instant#now()}.
   *
   * @return the system clock
   */
  static PrimeClock system() {
    return SystemClock.INSTANCE;
  }
}

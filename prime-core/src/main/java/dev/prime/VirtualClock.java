package dev.prime;

import java.time.Duration;
import java.time.Instant;
import java.util.Objects;

/**
 * A clock whose time moves only when {@link #advance(Duration)} is called: for tests and
 * simulations. Give it to a core with {@link CoreConfig.Builder#clock(PrimeClock)}; the core's
 * timers then tick as the test advances the time, as fast as the machine allows and the same way
 * every run (a 100 Hz timer gives exactly 1,000 ticks when the time is advanced by 10 s).
 *
 * <pre>{@code
 * VirtualClock clock = new VirtualClock();
 * try (PrimeCore core = new LibertyCore(CoreConfig.builder().clock(clock).build())) {
 *   Reader<Tick> ticks = core.timer("control", Duration.ofMillis(10)).reader();
 *   core.start();
 *   clock.advance(Duration.ofSeconds(10));   // 1,000 ticks, at once
 * }
 * }</pre>
 *
 * <p>Design note. The time is one long guarded by this object's monitor. A sleeper computes its
 * deadline and waits on the monitor until the time reaches it; {@link #advance} moves the time and
 * wakes every sleeper, each of which checks its own deadline. The wait is the monitor's, so an
 * interrupt ends it with {@link InterruptedException}. Thread-safe.
 */
public final class VirtualClock implements PrimeClock {
  private final Instant origin;
  private long nanos; // guarded by this

  /** A virtual clock at reading 0, whose {@link #now()} starts at 2000-01-01T00:00:00Z. */
  public VirtualClock() {
    this(Instant.parse("2000-01-01T00:00:00Z"));
  }

  /**
   * A virtual clock at reading 0 whose {@link #now()} starts at {@code origin}.
   *
   * @param origin the wall-clock time at reading 0
   */
  public VirtualClock(Instant origin) {
    this.origin = Objects.requireNonNull(origin, "origin must not be null");
  }

  /**
   * Moves the time forward and wakes every sleeper whose deadline it reached.
   *
   * @param amount how far; zero does nothing
   * @throws IllegalArgumentException if {@code amount} is negative (time never goes back), or if
   *     it would take the reading past {@code Long.MAX_VALUE} nanoseconds (about 292 years), the
   *     last a clock's reading holds; the time then stays where it was
   */
  public void advance(Duration amount) {
    Objects.requireNonNull(amount, "amount must not be null");
    if (amount.isNegative()) {
      throw new IllegalArgumentException(
          "a virtual clock never goes back: advance by zero or more, not " + amount);
    }
    synchronized (this) {
      try {
        nanos = Math.addExact(nanos, amount.toNanos());
      } catch (ArithmeticException pastTheEnd) {
        throw new IllegalArgumentException(
            "a virtual clock reads at most Long.MAX_VALUE ns (about 292 years): at "
                + Duration.ofNanos(nanos)
                + " it cannot advance by "
                + amount,
            pastTheEnd);
      }
      notifyAll();
    }
  }

  @Override
  public synchronized long nanoTime() {
    return nanos;
  }

  @Override
  public void sleepNanos(long duration) throws InterruptedException {
    synchronized (this) {
      sleepUntil(duration >= Long.MAX_VALUE - nanos ? Long.MAX_VALUE : nanos + Math.max(0, duration));
    }
  }

  /**
   * Waits until the time reaches {@code deadline}: until {@link #advance} moves it there.
   *
   * @param deadline a reading of {@link #nanoTime()}
   * @throws InterruptedException if the thread is interrupted while it waits
   */
  @Override
  public synchronized void sleepUntil(long deadline) throws InterruptedException {
    if (Thread.interrupted()) {
      throw new InterruptedException();
    }
    while (nanos < deadline) {
      wait();
    }
  }

  @Override
  public synchronized Instant now() {
    return origin.plusNanos(nanos);
  }

  @Override
  public synchronized String toString() {
    return "VirtualClock[" + Duration.ofNanos(nanos) + "]";
  }
}

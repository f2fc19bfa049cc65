package dev.prime.mcap;

/**
 * The time a replay at recorded speed paces itself by: a monotonic clock and a way to wait. The
 * system one is {@link #system()}; a test gives one whose {@link #sleepNanos} only advances its
 * own time, so a replay at recorded speed takes no real time.
 */
public interface ReplayClock {

  /** {@return a monotonic time in nanoseconds (only differences matter)} */
  long nanoTime();

  /**
   * Waits about {@code nanos} nanoseconds.
   *
   * @param nanos how long; never negative
   * @throws InterruptedException if the waiting thread is interrupted
   */
  void sleepNanos(long nanos) throws InterruptedException;

  /** {@return the system's clock: {@link System#nanoTime()} and a real sleep} */
  static ReplayClock system() {
    return SystemReplayClock.INSTANCE;
  }
}

/** {@link ReplayClock#system()}. */
enum SystemReplayClock implements ReplayClock {
  INSTANCE;

  @Override
  public long nanoTime() {
    return System.nanoTime();
  }

  @Override
  public void sleepNanos(long nanos) throws InterruptedException {
    java.util.concurrent.TimeUnit.NANOSECONDS.sleep(nanos);
  }
}

package dev.prime;

import java.time.Duration;
import java.time.Instant;

/** The machine's clock; see {@link PrimeClock#system()}. */
final class SystemClock implements PrimeClock {
  static final SystemClock INSTANCE = new SystemClock();

  private SystemClock() {}

  @Override
  public long nanoTime() {
    return System.nanoTime();
  }

  @Override
  public void sleepNanos(long nanos) throws InterruptedException {
    if (nanos > 0) {
      Thread.sleep(Duration.ofNanos(nanos).toMillis(), (int) (nanos % 1_000_000));
    } else if (Thread.interrupted()) {
      throw new InterruptedException();
    }
  }

  @Override
  public Instant now() {
    return Instant.now();
  }

  @Override
  public String toString() {
    return "PrimeClock.system()";
  }
}

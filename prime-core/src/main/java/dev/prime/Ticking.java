package dev.prime;

import java.time.DateTimeException;
import java.time.Instant;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.function.BiConsumer;

/**
 * The loop of a service driven by the core's clock: a timer ({@link PrimeCore#timer}) or the
 * ticking side of a sampler ({@link Source#sample}). Tick {@code n} is due {@code n} periods after
 * the origin; the loop sleeps on the {@link PrimeClock} until a tick is due and then calls the
 * action with its count and due time.
 *
 * <p>Design note. The origin is fixed once, by {@link #begin()}: when the core starts, or when the
 * service is declared on a started core. Due times are computed from it, never from the previous
 * wake-up, so ticks do not drift, and a loop that falls behind (a slow publish, a virtual clock
 * advanced by many periods at once) runs every tick that is due, in order, before it sleeps
 * again: a {@link VirtualClock} advanced by ten seconds gives exactly one thousand ticks of a 100
 * Hz timer. An action that throws goes to the error handler with the tick and the loop goes on;
 * so does a clock whose {@code sleepUntil} throws (the loop then waits a back-off and asks the
 * clock again for the same tick). An interrupt (the core closing) or the core's closing ends it.
 * It runs only where the service is hosted ({@link PrimeCore#isHostedHere}), and skips the ticks
 * due after its process lost the hosting to another.
 */
final class Ticking implements Runnable {

  private final PrimeCore core;
  private final String name;
  private final long periodNanos;
  private final BiConsumer<Long, Instant> action;
  private long originNanos; // guarded by this
  private Instant originTime; // guarded by this

  /**
   * @param core the core whose clock and error handler it uses
   * @param name the service's name
   * @param periodNanos the period, in the clock's nanoseconds, positive
   * @param action called with each tick's count (from 1) and due time
   */
  Ticking(PrimeCore core, String name, long periodNanos, BiConsumer<Long, Instant> action) {
    this.core = core;
    this.name = name;
    this.periodNanos = periodNanos;
    this.action = action;
  }

  /** Fixes the origin now, by the core's clock, unless it was fixed before. */
  synchronized void begin() {
    if (originTime == null) {
      PrimeClock clock = core.config().clock();
      originNanos = clock.nanoTime();
      originTime = clock.now();
    }
  }

  @Override
  public void run() {
    if (!core.isHostedHere(name)) {
      return;
    }
    begin();
    long origin;
    Instant time;
    synchronized (this) {
      origin = originNanos;
      time = originTime;
    }
    PrimeClock clock = core.config().clock();
    long count = 0;
    while (!Thread.currentThread().isInterrupted() && !core.isClosed()) {
      count++;
      long due;
      Instant dueTime;
      try {
        long sinceOrigin = Math.multiplyExact(count, periodNanos);
        due = Math.addExact(origin, sinceOrigin);
        dueTime = time.plusNanos(sinceOrigin);
      } catch (ArithmeticException | DateTimeException pastTheClock) {
        awaitTheEnd(); // this tick and every later one are due past what the clock can read
        return;
      }
      if (!sleepUntil(clock, due, count)) {
        return;
      }
      if (!core.isHostedHere(name)) {
        continue; // another process took the hosting over: it ticks now
      }
      try {
        action.accept(count, dueTime);
      } catch (CoreClosedException e) {
        if (core.isClosed()) {
          return;
        }
        report(count, e);
      } catch (VirtualMachineError e) {
        throw e;
      } catch (Throwable e) {
        report(count, e);
      }
    }
  }

  /**
   * Waits on the clock until tick {@code count} is {@code due}. A clock whose {@code sleepUntil}
   * throws is reported to the error handler with the tick's count, as a failed publish is, and
   * asked again after a back-off in real time (10 ms doubling up to 1 s, as a generic service's),
   * so a clock that keeps failing neither spins the core nor floods the handler, and one that
   * recovers publishes that tick, none skipped.
   *
   * @return whether the tick is due; false if the loop must end (an interrupt, the core closing)
   */
  private boolean sleepUntil(PrimeClock clock, long due, long count) {
    int failures = 0;
    while (true) {
      try {
        clock.sleepUntil(due);
        return true;
      } catch (InterruptedException e) {
        return false;
      } catch (VirtualMachineError e) {
        throw e;
      } catch (Throwable e) {
        if (Thread.currentThread().isInterrupted() || core.isClosed()) {
          return false;
        }
        report(count, e);
        failures++;
      }
      try {
        TimeUnit.NANOSECONDS.sleep(FailureBackoff.after(failures).toNanos());
      } catch (InterruptedException e) {
        return false;
      }
      if (core.isClosed()) {
        return false;
      }
    }
  }

  /**
   * Waits until the loop must end (an interrupt: the core closing), for a tick due past the last
   * reading the clock's long holds (a period of a century, from its third tick on), or at a time
   * past {@link Instant#MAX} (a clock whose {@code now()} starts near it): it is never due. It is
   * not taken as due at {@code Long.MAX_VALUE}, which a {@link VirtualClock} advanced to its end
   * reads: that would publish it, and every later tick, at once, stamped wrong.
   */
  private static void awaitTheEnd() {
    try {
      new CountDownLatch(1).await(); // counted down by no one: only an interrupt ends it
    } catch (InterruptedException e) {
      // the core closes: the loop ends, as after an interrupted sleep
    }
  }

  private void report(long count, Throwable error) {
    FailureReport.report(core.config().errorHandler(), name, count, error);
  }

}

package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.time.Duration;
import java.time.Instant;
import java.util.List;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicReference;
import org.junit.jupiter.api.Test;

/** The virtual clock: time moves only by advance, sleepers wake at their deadline, interrupts end sleeps. */
class VirtualClockTest {

  /** Starts a daemon thread running {@code sleep}; {@code woke} counts down when it returns or fails. */
  private static Thread sleeper(
      InterruptibleAction sleep, CountDownLatch woke, AtomicReference<Throwable> failure) {
    Thread thread =
        new Thread(
            () -> {
              try {
                sleep.run();
              } catch (Throwable e) {
                failure.set(e);
              } finally {
                woke.countDown();
              }
            });
    thread.setDaemon(true);
    thread.start();
    return thread;
  }

  private interface InterruptibleAction {
    void run() throws InterruptedException;
  }

  @Test
  void aSleeperUntilADeadlineWakesOnlyWhenVirtualTimeReachesIt() throws Exception {
    VirtualClock clock = new VirtualClock(Instant.parse("2030-01-01T00:00:00Z"));
    CountDownLatch woke = new CountDownLatch(1);
    AtomicReference<Throwable> failure = new AtomicReference<>();
    long deadline = Duration.ofSeconds(5).toNanos();
    Thread thread = sleeper(() -> clock.sleepUntil(deadline), woke, failure);
    clock.advance(Duration.ofSeconds(4));
    assertFalse(woke.await(200, TimeUnit.MILLISECONDS), "woke at 4 s of 5");
    clock.advance(Duration.ofSeconds(1));
    assertTrue(woke.await(10, TimeUnit.SECONDS), "did not wake at 5 s");
    thread.join(10_000);
    assertEquals(null, failure.get());
    assertEquals(deadline, clock.nanoTime());
    assertEquals(Instant.parse("2030-01-01T00:00:05Z"), clock.now());
  }

  @Test
  void aSleepLastsAtLeastItsDurationInVirtualTime() throws Exception {
    VirtualClock clock = new VirtualClock();
    CountDownLatch woke = new CountDownLatch(1);
    AtomicReference<Throwable> failure = new AtomicReference<>();
    long[] slept = new long[1];
    sleeper(
        () -> {
          long from = clock.nanoTime();
          clock.sleepNanos(Duration.ofSeconds(5).toNanos());
          slept[0] = clock.nanoTime() - from;
        },
        woke,
        failure);
    for (int second = 0; second < 30 && woke.getCount() > 0; second++) {
      clock.advance(Duration.ofSeconds(1));
      woke.await(50, TimeUnit.MILLISECONDS);
    }
    assertTrue(woke.await(10, TimeUnit.SECONDS), "never woke");
    assertEquals(null, failure.get());
    assertTrue(slept[0] >= Duration.ofSeconds(5).toNanos(), "slept " + slept[0] + " ns");
  }

  @Test
  void anInterruptEndsASleepWithInterruptedException() throws Exception {
    VirtualClock clock = new VirtualClock();
    CountDownLatch woke = new CountDownLatch(1);
    AtomicReference<Throwable> failure = new AtomicReference<>();
    Thread thread = sleeper(() -> clock.sleepNanos(Long.MAX_VALUE), woke, failure);
    thread.interrupt();
    assertTrue(woke.await(10, TimeUnit.SECONDS));
    assertTrue(failure.get() instanceof InterruptedException, String.valueOf(failure.get()));
  }

  /**
   * {@link PrimeClock#sleepNanos}: an interrupt ends the wait with {@link InterruptedException}
   * and "the interrupt flag is cleared, as by {@link Thread#sleep(long)}"; the same for {@link
   * PrimeClock#sleepUntil}, on the system clock and on a virtual clock.
   */
  @Test
  void anInterruptedSleepClearsTheFlagOnEveryClock() throws Exception {
    for (PrimeClock clock : List.of(PrimeClock.system(), new VirtualClock())) {
      for (String how : List.of("sleepNanos", "sleepUntil")) {
        CountDownLatch woke = new CountDownLatch(1);
        AtomicReference<Throwable> failure = new AtomicReference<>();
        AtomicReference<Boolean> flagAfter = new AtomicReference<>();
        long tenSeconds = Duration.ofSeconds(10).toNanos();
        Thread thread =
            sleeper(
                () -> {
                  try {
                    if (how.equals("sleepNanos")) {
                      clock.sleepNanos(tenSeconds);
                    } else {
                      clock.sleepUntil(clock.nanoTime() + tenSeconds);
                    }
                  } finally {
                    flagAfter.set(Thread.currentThread().isInterrupted());
                  }
                },
                woke,
                failure);
        thread.interrupt();
        assertTrue(woke.await(5, TimeUnit.SECONDS), clock + "." + how + " ended on the interrupt");
        assertTrue(
            failure.get() instanceof InterruptedException,
            clock + "." + how + ": " + failure.get());
        assertEquals(false, flagAfter.get(), clock + "." + how + " cleared the interrupt flag");
      }
    }
  }

  /**
   * {@link PrimeClock#sleepNanos}: "returns at once for zero or less", and {@link
   * PrimeClock#sleepUntil} "returns at once if it has" reached the deadline, on the system clock
   * (the bound, 1 s for the three calls, only tells a wait of a second from none).
   */
  @Test
  void theSystemClockDoesNotSleepForZeroOrLessOrAPassedDeadline() throws InterruptedException {
    PrimeClock clock = PrimeClock.system();
    long began = System.nanoTime();
    clock.sleepNanos(0);
    clock.sleepNanos(-Duration.ofSeconds(5).toNanos());
    clock.sleepUntil(clock.nanoTime() - Duration.ofSeconds(5).toNanos());
    long took = System.nanoTime() - began;
    assertTrue(took < Duration.ofSeconds(1).toNanos(), "took " + Duration.ofNanos(took));
  }

  @Test
  void zeroOrNegativeSleepsReturnAtOnceAndTimeNeverGoesBack() throws InterruptedException {
    VirtualClock clock = new VirtualClock();
    clock.sleepNanos(0);
    clock.sleepNanos(-5);
    IllegalArgumentException back =
        assertThrows(IllegalArgumentException.class, () -> clock.advance(Duration.ofNanos(-1)));
    assertTrue(back.getMessage().contains("never goes back"), back.getMessage());
    assertEquals(0, clock.nanoTime());
  }

  /** {@link VirtualClock#advance}: past the last reading a long holds, refused, time unchanged. */
  @Test
  void anAdvancePastTheLastReadingIsRefusedAndTheTimeStays() {
    VirtualClock clock = new VirtualClock();
    Duration century = Duration.ofDays(36_525);
    clock.advance(century.multipliedBy(2));
    long reading = clock.nanoTime();
    for (Duration tooFar : List.of(century, Duration.ofSeconds(Long.MAX_VALUE))) {
      IllegalArgumentException refused =
          assertThrows(IllegalArgumentException.class, () -> clock.advance(tooFar));
      assertTrue(refused.getMessage().contains("at most Long.MAX_VALUE ns"), refused.getMessage());
      assertEquals(reading, clock.nanoTime(), "the time stays where it was");
    }
    clock.advance(Duration.ofNanos(Long.MAX_VALUE - reading));
    assertEquals(Long.MAX_VALUE, clock.nanoTime(), "the last reading itself is reachable");
  }

  @Test
  void theSystemClockIsTheDefault() {
    assertEquals(PrimeClock.system(), CoreConfig.defaults().clock());
    VirtualClock clock = new VirtualClock();
    assertEquals(clock, CoreConfig.builder().clock(clock).build().toBuilder().build().clock());
    assertThrows(NullPointerException.class, () -> CoreConfig.builder().clock(null));
  }
}

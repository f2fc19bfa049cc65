package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.time.Duration;
import java.time.Instant;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicReference;
import org.junit.jupiter.api.Test;

/** The virtual clock: time moves only by advance, sleepers wake at their deadline, interrupts end sleeps. */
class VirtualClockTest {

  private static Thread sleeper(VirtualClock clock, long nanos, CountDownLatch woke, AtomicReference<Throwable> failure) {
    Thread thread =
        new Thread(
            () -> {
              try {
                clock.sleepNanos(nanos);
                woke.countDown();
              } catch (Throwable e) {
                failure.set(e);
                woke.countDown();
              }
            });
    thread.setDaemon(true);
    thread.start();
    return thread;
  }

  @Test
  void sleepersWakeOnlyWhenVirtualTimePassesTheirDeadline() throws Exception {
    VirtualClock clock = new VirtualClock(Instant.parse("2030-01-01T00:00:00Z"));
    CountDownLatch woke = new CountDownLatch(1);
    AtomicReference<Throwable> failure = new AtomicReference<>();
    Thread thread = sleeper(clock, Duration.ofSeconds(5).toNanos(), woke, failure);
    clock.advance(Duration.ofSeconds(4));
    assertFalse(woke.await(200, TimeUnit.MILLISECONDS), "woke at 4 s of 5");
    clock.advance(Duration.ofSeconds(1));
    assertTrue(woke.await(10, TimeUnit.SECONDS), "did not wake at 5 s");
    thread.join(10_000);
    assertEquals(null, failure.get());
    assertEquals(Duration.ofSeconds(5).toNanos(), clock.nanoTime());
    assertEquals(Instant.parse("2030-01-01T00:00:05Z"), clock.now());
  }

  @Test
  void anInterruptEndsASleepWithInterruptedException() throws Exception {
    VirtualClock clock = new VirtualClock();
    CountDownLatch woke = new CountDownLatch(1);
    AtomicReference<Throwable> failure = new AtomicReference<>();
    Thread thread = sleeper(clock, Long.MAX_VALUE, woke, failure);
    thread.interrupt();
    assertTrue(woke.await(10, TimeUnit.SECONDS));
    assertTrue(failure.get() instanceof InterruptedException, String.valueOf(failure.get()));
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

  @Test
  void theSystemClockIsTheDefault() {
    assertEquals(PrimeClock.system(), CoreConfig.defaults().clock());
    VirtualClock clock = new VirtualClock();
    assertEquals(clock, CoreConfig.builder().clock(clock).build().toBuilder().build().clock());
    assertThrows(NullPointerException.class, () -> CoreConfig.builder().clock(null));
  }
}

package dev.prime.mcap;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.fail;

import dev.prime.EventBlock;
import dev.prime.PrimeClock;
import dev.prime.VirtualClock;
import java.nio.file.Path;
import java.time.Duration;
import java.time.Instant;
import java.util.List;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.TimeoutException;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.io.TempDir;

/**
 * A replay at recorded speed on a {@link VirtualClock} that another thread advances (a test that
 * drives a core's timers and a replay by one clock): a value is fed once the clock reaches its
 * time, also when the clock moved between the replay reading it and starting to wait. {@link
 * PrimeClock#sleepUntil} is made for this; waiting for the difference read before oversleeps.
 */
class ReplayVirtualClockTest {
  @TempDir Path dir;

  private static final long GAP = Duration.ofMillis(100).toNanos();

  /**
   * A virtual clock whose given read is followed at once by an advance of {@link #GAP}, as if the
   * driving thread advanced it right after the replay read the time (deterministic, no sleeps).
   */
  static final class AdvancedAfterRead implements PrimeClock {
    final VirtualClock clock = new VirtualClock();
    private int readsBeforeAdvance;

    AdvancedAfterRead(int readsBeforeAdvance) {
      this.readsBeforeAdvance = readsBeforeAdvance;
    }

    @Override
    public synchronized long nanoTime() {
      long now = clock.nanoTime();
      if (--readsBeforeAdvance == 0) {
        clock.advance(Duration.ofNanos(GAP));
      }
      return now;
    }

    @Override
    public void sleepNanos(long nanos) throws InterruptedException {
      clock.sleepNanos(nanos);
    }

    @Override
    public void sleepUntil(long deadline) throws InterruptedException {
      clock.sleepUntil(deadline);
    }

    @Override
    public Instant now() {
      return clock.now();
    }
  }

  @Test
  void aValueIsFedOnceTheClockReachesItsTimeThoughTheClockMovedMeanwhile() throws Exception {
    Path file = dir.resolve("ticks.mcap");
    try (McapWriter writer = McapWriter.open(file, McapWriterOptions.defaults().synchronous())) {
      McapChannel<Integer> ticks = writer.channel("ticks", Integer.class);
      ticks.write(0, 0, 0, 0);
      ticks.write(GAP, GAP, 1, 1);
    }
    // read 1: the first value's start; read 2: the time the second value's wait is computed from
    AdvancedAfterRead clock = new AdvancedAfterRead(2);
    List<Integer> fed = new CopyOnWriteArrayList<>();
    EventBlock<Integer> ticks = new EventBlock<>();
    ticks.subscribe(fed::add);

    CompletableFuture<ReplayResult> result = new CompletableFuture<>();
    Thread replaying = new Thread(() -> {
      try {
        result.complete(McapReplay.of(file).feed("ticks", ticks, Integer.class)
            .options(ReplayOptions.recordedSpeed(clock)).run());
      } catch (Throwable e) {
        result.completeExceptionally(e);
      }
    }, "replaying");
    replaying.setDaemon(true);
    replaying.start();
    try {
      assertEquals(2, result.get(20, TimeUnit.SECONDS).total());
    } catch (TimeoutException e) {
      replaying.interrupt();
      fail("the replay still waits for the second value, though the clock is at " + clock.clock
          + " and the value is due at " + Duration.ofNanos(GAP) + "; fed " + fed);
    }
    assertEquals(List.of(0, 1), fed);
  }
}

package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Source;
import java.time.Duration;
import java.util.Set;
import java.util.concurrent.CountDownLatch;
import org.junit.jupiter.api.Assumptions;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.function.Executable;

/**
 * A {@code start()} that throws leaves the core failed to start ({@link PrimeCore#start()}): a
 * second {@code start()} and every declaration are refused with an {@link
 * IllegalStateException} that says so, quotes the failure (its cause) and says to close the core
 * and make a new one; a publish is as before a start; no {@code whenRunning} hook starts, each
 * one's {@code onClose} runs at {@code close()}, which leaves no thread. The
 * failure is a host the topology lacks ({@link #newCoreHosting}): only a media of several
 * processes has a {@code start()} that can fail, the others run every service they declare.
 */
public interface FailedStartConformance extends GenericServiceConformance {

  @Test
  default void aCoreWhoseStartFailedRefusesStartAndDeclarationsAndClosesClean()
      throws InterruptedException {
    CoreConfig config =
        CoreConfig.builder().name("kit-failed-start-" + Long.toString(System.nanoTime(), 36)).build();
    PrimeCore core = newCoreHosting(config, Set.of("double", "nowhere"));
    Assumptions.assumeTrue(
        core != null,
        "this media runs every service it declares and has no start() that can fail");
    CountDownLatch hookStarted = new CountDownLatch(2);
    CountDownLatch hookClosed = new CountDownLatch(2);
    try {
      Chain<Integer, Integer> unused = core.chain("unused", (Integer x) -> x + 1);
      Block<Integer, Integer> doubled = core.chain("double", (Integer x) -> x * 2).toBlock();
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("ticks", events);
      core.whenRunning("before", hookStarted::countDown, hookClosed::countDown);
      RuntimeException failure = assertThrows(RuntimeException.class, core::start);
      core.whenRunning("after", hookStarted::countDown, hookClosed::countDown);
      assertTrue(failure.getMessage().contains("nowhere"), failure.getMessage());

      assertRefused(failure, "a second start()", core::start);
      assertRefused(failure, "a declaration", () -> core.chain("late", (Integer x) -> x));
      assertRefused(failure, "a declaration", () -> core.source("late-source", new EventBlock<>()));
      assertRefused(failure, "a declaration", unused::toBlock);
      assertRefused(failure, "a declaration", () -> core.link(source, unused));
      assertRefused(failure, "a declaration", () -> source.filter(x -> x > 0));
      assertRefused(failure, "a declaration", () -> core.timer("late-timer", Duration.ofSeconds(1)));
      assertRefused(failure, "a declaration", () -> core.merge(source, source));
      assertRefused(failure, "a declaration", () -> core.service("late-service", () -> {}));
      assertFalse(core.topology().node("late").isPresent(), "a refused declaration leaves nothing");
      if (!publishesBeforeStartWait()) { // as before a start: refused at once
        assertThrows(IllegalStateException.class, () -> events.publish(1));
        assertThrows(IllegalStateException.class, () -> doubled.process(1));
      }
      assertTrue(core.isStarted() && !core.isClosed(), "accepted, failed, not closed");
      assertEquals(2, hookStarted.getCount(), "no whenRunning hook starts");
    } finally {
      core.close();
    }
    assertEquals(0, hookClosed.getCount(), "each hook's onClose ran at close()");
    awaitNoThreadsLeft(core);
  }

  private static void assertRefused(Throwable failure, String what, Executable action) {
    IllegalStateException refused = assertThrows(IllegalStateException.class, action);
    assertSame(failure, refused.getCause(), "the refusal carries the start's failure: " + refused);
    String message = refused.getMessage();
    assertTrue(message.contains(what), "says what is refused (" + what + "): " + message);
    assertTrue(
        message.contains("failed to start") && message.contains(failure.getMessage()),
        "quotes the failure: " + message);
    assertTrue(
        message.contains("close() it") && message.contains("make a new core"),
        "says what to do: " + message);
  }
}

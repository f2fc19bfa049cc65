package dev.prime.conformance;

import static dev.prime.conformance.ConformanceBase.assertNoThreadsLeft;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.ChainFailedException;
import dev.prime.CoreClosedException;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.Isolated;
import dev.prime.PrimeCore;
import dev.prime.PrimeException;
import dev.prime.Reader;
import dev.prime.Repeat;
import dev.prime.Source;
import dev.prime.Token;
import java.time.Duration;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicBoolean;
import java.util.concurrent.atomic.AtomicInteger;
import java.util.concurrent.atomic.AtomicReference;
import org.junit.jupiter.api.Test;

/**
 * Every blocking wait honours interruption and {@code close()}: a repeater, a caller waiting for
 * an isolated chain, a sync collector and a reader; and {@code close()} called from a service's
 * own thread returns at once and leaves no thread.
 */
public interface InterruptConformance extends ConformanceBase {

  /** A thread that runs one call and keeps what it threw; bounded by the kit's patience. */
  final class Caller {
    final Thread thread;
    final AtomicReference<Throwable> thrown = new AtomicReference<>();
    final CountDownLatch ended = new CountDownLatch(1);
    volatile boolean interruptedAtEnd;

    Caller(String name, Callable call) {
      thread =
          new Thread(
              () -> {
                try {
                  call.run();
                } catch (Throwable t) {
                  thrown.set(t);
                } finally {
                  interruptedAtEnd = Thread.currentThread().isInterrupted();
                  ended.countDown();
                }
              },
              "kit-caller-" + name);
      thread.setDaemon(true);
      thread.start();
    }

    /** Waits until the call ended, failing the test if it did not within {@code patience}. */
    Throwable awaitFailure(Duration patience) throws InterruptedException {
      assertTrue(
          ended.await(patience.toMillis(), TimeUnit.MILLISECONDS),
          "the call did not end within " + patience);
      return thrown.get();
    }

    /**
     * Waits, at most 300 ms in all, until each of {@code callers} waits in a monitor or a park
     * (or ended), so that what the test does next likely meets blocked calls. A media that waits
     * in a socket read stays runnable, and then the bound passes; the test's assertions hold
     * either way.
     */
    static void awaitBlocked(List<Caller> callers) throws InterruptedException {
      long deadline = System.nanoTime() + TimeUnit.MILLISECONDS.toNanos(300);
      for (Caller caller : callers) {
        while (caller.ended.getCount() > 0 && System.nanoTime() < deadline) {
          Thread.State state = caller.thread.getState();
          if (state == Thread.State.WAITING
              || state == Thread.State.TIMED_WAITING
              || state == Thread.State.BLOCKED) {
            break;
          }
          caller.ended.await(5, TimeUnit.MILLISECONDS);
        }
      }
    }
  }

  /**
   * Waits, at most 300 ms, until the threads of {@code core} whose name mentions {@code service}
   * wait (in a monitor or a park), so that what the test does next meets them waiting. A media
   * whose threads are named otherwise, or wait in a socket read, passes the bound; the test's
   * assertions hold either way.
   */
  private static void awaitWaiting(PrimeCore core, String service) throws InterruptedException {
    long deadline = System.nanoTime() + TimeUnit.MILLISECONDS.toNanos(300);
    CountDownLatch never = new CountDownLatch(1);
    String prefix = "prime-" + core.name() + "-";
    while (System.nanoTime() < deadline) {
      boolean waiting = false;
      for (Thread thread : Thread.getAllStackTraces().keySet()) {
        if (thread.getName().startsWith(prefix) && thread.getName().contains(service)) {
          Thread.State state = thread.getState();
          waiting = state == Thread.State.WAITING || state == Thread.State.TIMED_WAITING;
        }
      }
      if (waiting) {
        return;
      }
      never.await(1, TimeUnit.MILLISECONDS); // a bounded pause
    }
  }

  /** A call that may throw anything. */
  @FunctionalInterface
  interface Callable {
    void run() throws Exception;
  }

  @Test
  default void closeStopsARepeaterThatNeverSaysStop() throws InterruptedException {
    CountDownLatch looping = new CountDownLatch(100);
    PrimeCore core = newCore();
    Caller caller;
    try (core) {
      Chain<Integer, Integer> forever =
          core.repeater(
              core.chain(
                  "round",
                  x -> {
                    looping.countDown();
                    return x + 1;
                  }),
              (Integer in, Integer out, List<Void> none) -> Repeat.again(out));
      core.start();
      Block<Integer, Integer> block = forever.toBlock();
      caller = new Caller("repeater", () -> block.process(0));
      assertTrue(looping.await(patience().toMillis(), TimeUnit.MILLISECONDS));
    }
    assertInstanceOf(PrimeException.class, caller.awaitFailure(patience()), "the loop ended");
    assertNoThreadsLeft(core);
  }

  /**
   * architecture.md (waits): "after {@code close()} a repeater stops within one round", with a
   * {@link CoreClosedException} (the core's open check between rounds). A repeater that never
   * says stop runs when the core closes: its caller gets a {@code CoreClosedException}, and at
   * most one round starts after {@code close()} returned (the one whose check passed just
   * before).
   */
  @Test
  default void closeEndsARepeaterWithCoreClosedExceptionWithinOneRound()
      throws InterruptedException {
    CountDownLatch looping = new CountDownLatch(100);
    AtomicInteger rounds = new AtomicInteger();
    PrimeCore core = newCore();
    Caller caller;
    int atClose;
    try {
      Chain<Integer, Integer> forever =
          core.repeater(
              core.chain(
                  "counted-round",
                  x -> {
                    rounds.incrementAndGet();
                    looping.countDown();
                    return x + 1;
                  }),
              (Integer in, Integer out, List<Void> none) -> Repeat.again(out));
      core.start();
      Block<Integer, Integer> block = forever.toBlock();
      caller = new Caller("closed-repeater", () -> block.process(0));
      assertTrue(looping.await(patience().toMillis(), TimeUnit.MILLISECONDS), "it loops");
    } finally {
      core.close();
      atClose = rounds.get();
    }
    Throwable failure = caller.awaitFailure(patience());
    assertInstanceOf(CoreClosedException.class, failure, "the loop ended with: " + failure);
    assertNoThreadsLeft(core);
    int after = rounds.get() - atClose;
    assertTrue(after <= 1, after + " rounds started after close() returned, not at most one");
  }

  @Test
  default void interruptingItsCallerStopsARepeater() throws InterruptedException {
    CountDownLatch looping = new CountDownLatch(100);
    AtomicBoolean nextCallEnded = new AtomicBoolean();
    CountDownLatch roundAfterTheNextCall = new CountDownLatch(1);
    try (PrimeCore core = newCore()) {
      // a non-negative input loops for ever; a negative one stops at once
      Chain<Integer, Integer> forever =
          core.repeater(
              core.chain(
                  x -> {
                    looping.countDown();
                    if (x >= 0 && nextCallEnded.get()) {
                      roundAfterTheNextCall.countDown();
                    }
                    return x + 1;
                  }),
              (Integer in, Integer out, List<Void> none) ->
                  in < 0 ? Repeat.stop(in) : Repeat.again(out));
      core.start();
      Block<Integer, Integer> block = forever.toBlock();
      Caller caller = new Caller("repeater", () -> block.process(0));
      assertTrue(looping.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      caller.thread.interrupt();
      assertInstanceOf(PrimeException.class, caller.awaitFailure(patience()));
      assertTrue(caller.interruptedAtEnd, "the caller's interrupt flag stays set");
      // the loop stopped (wherever it ran): the repeater serves the next call
      AtomicReference<Integer> next = new AtomicReference<>();
      Caller nextCaller = new Caller("next", () -> next.set(block.process(-1)));
      assertNull(nextCaller.awaitFailure(patience()), "the next call of the repeater fails");
      assertEquals(-1, next.get(), "the next call gets its own conclusion");
      nextCallEnded.set(true);
      // a bounded wait for a round that must not come
      assertFalse(
          roundAfterTheNextCall.await(300, TimeUnit.MILLISECONDS),
          "the interrupted caller's loop runs no more rounds");
    }
  }

  @Test
  default void aCallerWaitingForAnIsolatedChainHonoursInterruption() throws InterruptedException {
    CountDownLatch entered = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    CountDownLatch ranForTheWaiter = new CountDownLatch(1);
    try (PrimeCore core = newCore()) {
      Isolated<Integer, Integer> isolated =
          holdingIsolate(core, entered, release, ranForTheWaiter);
      Block<Integer, Integer> holder = isolated.newUser().toBlock();
      Block<Integer, Integer> waiter = isolated.newUser().toBlock();
      core.start();
      Caller holding = new Caller("holder", () -> holder.process(1));
      try {
        assertTrue(entered.await(patience().toMillis(), TimeUnit.MILLISECONDS));
        Caller waiting = new Caller("waiter", () -> waiter.process(2));
        awaitItsTurn(waiting);
        waiting.thread.interrupt();
        assertInstanceOf(PrimeException.class, waiting.awaitFailure(patience()));
        assertTrue(waiting.interruptedAtEnd, "the waiter's interrupt flag stays set");
      } finally {
        release.countDown();
      }
      holding.awaitFailure(patience());
      assertEquals(3, holder.process(3), "the isolated chain goes on");
      // IsolateBlock: "the block is not run for it" (a bounded wait for a run that must not come)
      assertFalse(
          ranForTheWaiter.await(500, TimeUnit.MILLISECONDS),
          "the isolated block is not run for a waiter that was interrupted");
    }
  }

  /**
   * IsolateBlock: calls run "in the order they came (first come, first served), so no caller
   * starves", and a waiter that gives up does not change the order of those behind it. Three
   * users come one after another while a fourth holds the chain (each given time to reach it),
   * the second is interrupted, and the holder holds on a further 300 ms, longer than the wait's
   * 50 ms slices.
   */
  @Test
  default void callersWaitingForAnIsolatedChainGetItInTheOrderTheyCame()
      throws InterruptedException {
    CountDownLatch entered = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    List<Integer> ran = new java.util.concurrent.CopyOnWriteArrayList<>();
    try (PrimeCore core = newCore()) {
      Isolated<Integer, Integer> isolated = holdingIsolate(core, 0, entered, release, ran::add);
      Block<Integer, Integer> holder = isolated.newUser().toBlock();
      List<Block<Integer, Integer>> users = new ArrayList<>();
      for (int i = 0; i < 4; i++) {
        users.add(isolated.newUser().toBlock());
      }
      core.start();
      Caller holding = new Caller("holder", () -> holder.process(0));
      List<Caller> waiting = new ArrayList<>();
      try {
        assertTrue(entered.await(patience().toMillis(), TimeUnit.MILLISECONDS));
        for (int i = 1; i <= 4; i++) {
          int value = i;
          Caller caller = new Caller("waiter-" + i, () -> users.get(value - 1).process(value));
          awaitItsTurn(caller);
          // 25 ms apart, so that waits taken in 50 ms slices would not keep the callers' order
          assertFalse(caller.ended.await(25, TimeUnit.MILLISECONDS), "waiter " + i + " waits");
          waiting.add(caller);
        }
        waiting.get(1).thread.interrupt();
        assertInstanceOf(PrimeException.class, waiting.get(1).awaitFailure(patience()));
        assertFalse(
            waiting.get(0).ended.await(300, TimeUnit.MILLISECONDS),
            "the first waiter waits while the holder holds the isolated chain");
      } finally {
        release.countDown();
      }
      assertEquals(null, holding.awaitFailure(patience()));
      for (int i : new int[] {0, 2, 3}) {
        assertEquals(null, waiting.get(i).awaitFailure(patience()), "waiter " + (i + 1));
      }
      assertEquals(
          List.of(0, 1, 3, 4),
          ran,
          "the waiting callers ran in the order they came, without the one interrupted");
    }
  }

  @Test
  default void aCallerWaitingForAnIsolatedChainEndsWhenTheCoreCloses()
      throws InterruptedException {
    CountDownLatch entered = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    PrimeCore core = newCore();
    try {
      Isolated<Integer, Integer> isolated =
          holdingIsolate(core, entered, release);
      Block<Integer, Integer> holder = isolated.newUser().toBlock();
      Block<Integer, Integer> waiter = isolated.newUser().toBlock();
      core.start();
      Caller holding = new Caller("holder", () -> holder.process(1));
      assertTrue(entered.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      Caller waiting = new Caller("waiter", () -> waiter.process(2));
      awaitItsTurn(waiting);
      core.close();
      Throwable failure = waiting.awaitFailure(patience());
      assertInstanceOf(CoreClosedException.class, failure, "the waiter ends with CoreClosedException");
      release.countDown();
      holding.awaitFailure(patience());
    } finally {
      release.countDown();
      core.close();
    }
  }

  /**
   * A block of an isolated chain that calls the same isolated chain (through another user) on
   * the thread that runs it would wait for itself: misuse, which never hangs (architecture,
   * <i>Errors</i>). On every media the inner call fails at once with an {@link
   * IllegalStateException} that says so (on Optimus it is made on the thread of the isolated
   * chain's service, in the process that hosts it), the outer call fails with it, and the chain
   * serves the next call. What a media cannot see (a call handed to another thread) is not
   * promised.
   */
  @Test
  default void anIsolatedChainCalledFromInsideItselfFailsInsteadOfWaitingForItself()
      throws InterruptedException {
    assertAFailedCallFromInsideItself(
        (core, inner) ->
          core.chain(
              "counter",
              (Integer x) -> x > 0 ? inner.get().process(x - 1) + 1 : 0));
  }

  /**
   * As above, the call made by the later chain of a linked isolated chain (on Optimus a service
   * of its own, on a thread of its own).
   */
  @Test
  default void aLinkedIsolatedChainCalledFromItsLaterChainFailsInsteadOfWaitingForItself()
      throws InterruptedException {
    assertAFailedCallFromInsideItself(
        (core, inner) ->
          core.link(
              core.chain("take", (Integer x) -> x),
              core.chain(
                  "count", (Integer x) -> x > 0 ? inner.get().process(x - 1) + 1 : 0)));
  }

  /**
   * As above, the call made by a chain a template isolated chain was made of (on Optimus a
   * service of its own that the template's service calls).
   */
  @Test
  default void anIsolatedTemplateCalledFromOneOfItsChainsFailsInsteadOfWaitingForItself()
      throws InterruptedException {
    assertAFailedCallFromInsideItself(
        (core, inner) ->
          core.ifThenElse(
              (Integer x) -> x > 0,
              core.chain("count", (Integer x) -> inner.get().process(x - 1) + 1),
              core.chain("zero", (Integer x) -> 0)));
  }

  /**
   * As above, the call made by a chain the isolated chain's block calls through a block it was
   * given ({@code toBlock()} of a chain it did not consume): on Liberty and Radiant that chain
   * runs inline, on Optimus it is a service of its own, on another thread, whose call the isolated
   * chain's service waits for in the same process.
   */
  @Test
  default void anIsolatedChainCalledBackByAChainItCallsFailsInsteadOfWaitingForItself()
      throws InterruptedException {
    assertAFailedCallFromInsideItself(
        (core, inner) -> {
          Block<Integer, Integer> helper =
              core.chain("helper", (Integer x) -> inner.get().process(x) + 1).toBlock();
          return core.chain("counter", (Integer x) -> x > 0 ? helper.process(x - 1) : 0);
        });
  }

  /**
   * As above, the call made by the chain an isolated repeater runs (on Optimus a service of its
   * own that the repeater's service calls, round after round).
   */
  @Test
  default void anIsolatedRepeaterCalledFromItsChainFailsInsteadOfWaitingForItself()
      throws InterruptedException {
    assertAFailedCallFromInsideItself(
        (core, inner) ->
          core.repeater(
              core.chain(
                  "round", (Integer x) -> x > 0 ? inner.get().process(x - 1) + 1 : 0),
              (Integer in, Integer out, List<Void> none) -> Repeat.stop(out)));
  }

  /**
   * As above, with the user the block calls made after the start ({@link Isolated#newUser} on a
   * started core, which {@code TemplateConformance} checks serves calls): that user refuses the
   * call from inside the chain at once too.
   */
  @Test
  default void anIsolatedChainCalledFromInsideItselfThroughAUserMadeAfterTheStartFails()
      throws InterruptedException {
    AtomicReference<Block<Integer, Integer>> inner = new AtomicReference<>();
    PrimeCore core = newCore();
    try {
      Isolated<Integer, Integer> isolated =
          core.isolate(
              core.chain(
                  "counter",
                  (Integer x) -> x > 0 ? inner.get().process(x - 1) + 1 : 0));
      Block<Integer, Integer> outer = isolated.newUser().toBlock();
      core.start();
      inner.set(isolated.newUser().toBlock());
      assertEquals(0, outer.process(0), "a call that does not re-enter");
      assertAFailedReentry(outer, inner);
    } finally {
      core.close();
    }
  }

  /**
   * A chain whose block calls its own chain (recursion through the block {@code toBlock()} made)
   * never waits for itself (architecture, <i>Errors</i>): where the whole call runs on the
   * caller's thread (Liberty, Radiant) it recurses as a method would; where the chain is a service
   * that takes one request at a time (Optimus), the inner call fails at once with an {@link
   * IllegalStateException} that says so, the outer call with it, and the chain serves the next
   * call.
   */
  @Test
  default void aChainThatCallsItselfRecursesOnTheCallersThreadOrFailsAtOnce()
      throws InterruptedException {
    assertACallOfItsOwnChain(
        (core, self) ->
            core.chain("counter", (Integer x) -> x > 0 ? self.get().process(x - 1) + 1 : 0));
  }

  /** As above, a linked chain called by its later chain (on Optimus a service of its own). */
  @Test
  default void aLinkedChainCalledFromItsLaterChainRecursesOnTheCallersThreadOrFailsAtOnce()
      throws InterruptedException {
    assertACallOfItsOwnChain(
        (core, self) ->
            core.link(
                core.chain("take", (Integer x) -> x),
                core.chain(
                    "count", (Integer x) -> x > 0 ? self.get().process(x - 1) + 1 : 0)));
  }

  /**
   * As above, a chain called back by a chain its block calls ({@code ping} calls {@code pong},
   * whose block calls {@code ping}): on Optimus {@code ping}'s service waits for {@code pong}'s,
   * which runs on another thread, and the call back is refused at once there, not after the call
   * timeout.
   */
  @Test
  default void aChainCalledBackByAChainItCallsRecursesOnTheCallersThreadOrFailsAtOnce()
      throws InterruptedException {
    assertACallOfItsOwnChain(
        (core, self) -> {
          Block<Integer, Integer> pong =
              core.chain("pong", (Integer x) -> self.get().process(x)).toBlock();
          return core.chain("ping", (Integer x) -> x > 0 ? pong.process(x - 1) + 1 : 0);
        });
  }

  /**
   * As above, a template called by one of its parts (the branch of an {@code ifThenElse} calls
   * the template): on Optimus the template's service waits for the part's, and the part's call of
   * the template is refused at once, not after the call timeout.
   */
  @Test
  default void aTemplateCalledByItsPartRecursesOnTheCallersThreadOrFailsAtOnce()
      throws InterruptedException {
    assertACallOfItsOwnChain(
        (core, self) ->
            core.ifThenElse(
                (Integer x) -> x > 0,
                core.chain("count-down", (Integer x) -> self.get().process(x - 1) + 1),
                core.chain("at-zero", (Integer x) -> 0)));
  }

  /**
   * A chain whose block calls its own chain without end (architecture, <i>Errors</i>, "A chain
   * that calls itself"): where the call runs on the caller's thread (Liberty, Radiant) it recurses
   * until the stack's limit, and the {@link StackOverflowError} reaches the caller unwrapped;
   * where the chain is a service (Optimus), the inner call fails at once. Either way the chain
   * then serves the next call.
   */
  @Test
  default void aChainThatCallsItselfWithoutEndEndsAtTheStackLimitOrFailsAtOnce()
      throws InterruptedException {
    AtomicReference<Block<Integer, Integer>> self = new AtomicReference<>();
    try (PrimeCore core = newCore()) {
      Block<Integer, Integer> chain =
          core.chain("endless", (Integer x) -> x == 0 ? 0 : self.get().process(x + 1) + 1)
              .toBlock();
      self.set(chain);
      core.start();
      Caller recursing = new Caller("endless-recursion", () -> chain.process(1));
      Throwable failure = recursing.awaitFailure(patience());
      if (blocksRunOnTheCallersThread()) {
        assertInstanceOf(StackOverflowError.class, failure, "the stack's limit, unwrapped");
      } else {
        ChainFailedException outer =
            assertInstanceOf(ChainFailedException.class, failure, "the outer call fails");
        assertEquals("endless", outer.chainName(), "names the chain whose block made the call");
        assertInstanceOf(
            IllegalStateException.class, failure.getCause(), "the inner call's failure: " + failure);
      }
      assertEquals(0, chain.process(0), "the chain serves the next call");
    }
  }

  /**
   * On a new core, makes the block of the chain {@code recursive} makes (whose block calls {@code
   * self}, set here to that very block), and calls it with 3: 3 where blocks run on the caller's
   * thread, else a failure whose cause is the inner call's IllegalStateException; then with 0.
   */
  private void assertACallOfItsOwnChain(
      java.util.function.BiFunction<
              PrimeCore, AtomicReference<Block<Integer, Integer>>, Chain<Integer, Integer>>
          recursive)
      throws InterruptedException {
    AtomicReference<Block<Integer, Integer>> self = new AtomicReference<>();
    try (PrimeCore core = newCore()) {
      Block<Integer, Integer> chain = recursive.apply(core, self).toBlock();
      self.set(chain);
      core.start();
      assertEquals(0, chain.process(0), "a call that does not recurse");
      if (blocksRunOnTheCallersThread()) {
        assertEquals(3, chain.process(3), "the chain recursed three times");
      } else {
        Caller recursing = new Caller("recursing", () -> chain.process(3));
        Throwable failure = recursing.awaitFailure(patience());
        assertInstanceOf(ChainFailedException.class, failure, "the outer call fails");
        Throwable cause = failure.getCause();
        assertInstanceOf(IllegalStateException.class, cause, "the inner call's failure: " + failure);
        assertTrue(cause.getMessage().contains("from inside itself"), "says what is wrong: " + cause);
      }
      assertEquals(0, chain.process(0), "the chain serves the next call");
    }
  }

  /**
   * On a new core, isolates the chain {@code shared} makes (whose block calls {@code inner}) and
   * checks it as {@link #assertAFailedCallFromInsideItself(PrimeCore, Isolated, AtomicReference)}.
   */
  private void assertAFailedCallFromInsideItself(
      java.util.function.BiFunction<
              PrimeCore, AtomicReference<Block<Integer, Integer>>, Chain<Integer, Integer>>
          shared)
      throws InterruptedException {
    AtomicReference<Block<Integer, Integer>> inner = new AtomicReference<>();
    PrimeCore core = newCore();
    try {
      assertAFailedCallFromInsideItself(core, core.isolate(shared.apply(core, inner)), inner);
    } finally {
      core.close();
    }
  }

  /**
   * Calls {@code isolated} through a new user with 0 (no re-entry) and with 1 (its block calls
   * {@code inner}, set here to another user): the second fails with the inner call's
   * IllegalStateException, and the chain then serves the next call.
   */
  private void assertAFailedCallFromInsideItself(
      PrimeCore core,
      Isolated<Integer, Integer> isolated,
      AtomicReference<Block<Integer, Integer>> inner)
      throws InterruptedException {
    Block<Integer, Integer> outer = isolated.newUser().toBlock();
    inner.set(isolated.newUser().toBlock());
    core.start();
    assertEquals(0, outer.process(0), "a call that does not re-enter");
    assertAFailedReentry(outer, inner);
  }

  /**
   * Calls {@code outer} with 1, whose block calls {@code inner}, a user of the same isolated
   * chain: the call fails with the inner call's IllegalStateException, and the chain then serves
   * the next call.
   */
  private void assertAFailedReentry(
      Block<Integer, Integer> outer, AtomicReference<Block<Integer, Integer>> inner)
      throws InterruptedException {
    Caller reentering = new Caller("reentering", () -> outer.process(1));
    Throwable failure = reentering.awaitFailure(patience());
    Throwable cause = failure;
    while (cause != null && !(cause instanceof IllegalStateException)) {
      cause = cause.getCause();
    }
    assertInstanceOf(IllegalStateException.class, cause, "the inner call's failure: " + failure);
    assertTrue(cause.getMessage().contains("from inside itself"), "says what is wrong: " + cause);
    assertEquals(0, inner.get().process(0), "the isolated chain serves the next call");
  }

  /**
   * A sync collector of another core's source is a blocking wait of its own core: it ends with
   * {@link CoreClosedException} when that core closes, the other core and its source open
   * ({@link PrimeCore}: "Every blocking wait ... ends when its thread is interrupted or the core
   * closes"). Collecting again after the close, also with an async collector, is refused the same
   * way.
   */
  @Test
  default void aSyncCollectorOfAnotherCoresSourceEndsItsWaitWhenItsOwnCoreCloses()
      throws InterruptedException {
    try (PrimeCore other = newCore()) {
      Source<Integer> shared = other.source("shared", new EventBlock<Integer>());
      other.start();
      PrimeCore core = newCore();
      Block<Token, Integer> collect = core.syncCollector(shared).toBlock();
      Block<Token, List<Integer>> collectAll = core.asyncCollector(shared).toBlock();
      core.start();
      Caller waiting = new Caller("collector", () -> collect.process(Token.INSTANCE));
      Caller.awaitBlocked(List.of(waiting));
      core.close();
      Throwable failure = waiting.awaitFailure(patience());
      assertInstanceOf(CoreClosedException.class, failure, "the wait ended with its core's close");
      assertTrue(failure.getMessage().contains("'" + core.name() + "'"), "names the core: " + failure);
      Caller again = new Caller("again", () -> collect.process(Token.INSTANCE));
      assertInstanceOf(CoreClosedException.class, again.awaitFailure(patience()));
      Caller all = new Caller("all", () -> collectAll.process(Token.INSTANCE));
      assertInstanceOf(
          CoreClosedException.class, all.awaitFailure(patience()), "an async collector too");
    }
  }

  /**
   * A sync collector's call that waits honours interruption and takes no value with it: the
   * values published after it ended go to the next calls, in order (wherever the collector's
   * wait ran: on Optimus a service's, which learns that its caller gave up).
   */
  @Test
  default void aSyncCollectorWaitingForAValueHonoursInterruption() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Chain<Token, Integer> collector = core.syncCollector(core.source(events));
      core.start();
      Block<Token, Integer> block = collector.toBlock();
      Caller caller = new Caller("collector", () -> block.process(Token.INSTANCE));
      Caller.awaitBlocked(List.of(caller));
      caller.thread.interrupt();
      assertInstanceOf(PrimeException.class, caller.awaitFailure(patience()));
      assertTrue(caller.interruptedAtEnd, "the caller's interrupt flag stays set");
      events.publish(1);
      events.publish(2);
      List<Integer> next = new ArrayList<>();
      Caller nextCalls =
          new Caller(
              "collector-next",
              () -> {
                next.add(block.process(Token.INSTANCE));
                next.add(block.process(Token.INSTANCE));
              });
      assertNull(nextCalls.awaitFailure(patience()), "the next calls fail");
      assertEquals(List.of(1, 2), next, "the next calls get the values published after the interrupt");
    }
  }

  @Test
  default void aReaderWaitingInTakeHonoursInterruption() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      Reader<Integer> reader = core.source(new EventBlock<Integer>()).reader();
      core.start();
      Caller untimed = new Caller("take", reader::take);
      untimed.thread.interrupt();
      assertInstanceOf(InterruptedException.class, untimed.awaitFailure(patience()));
      Reader<Integer> other = core.source(new EventBlock<Integer>()).reader();
      Caller timed = new Caller("take-timeout", () -> other.take(Duration.ofHours(1)));
      timed.thread.interrupt();
      assertInstanceOf(InterruptedException.class, timed.awaitFailure(patience()));
    }
  }

  /**
   * {@link Reader#take()}: "InterruptedException if the thread is interrupted ... while waiting
   * (within about a second on a media that waits on the network); a value not yet handed out
   * stays for the next call". A take and a timed take interrupted while they wait, on a reader of
   * an event source and on one of a service's output, end within 3 s (about a second on a busy
   * machine) and take nothing with them: the values published afterwards all reach the next
   * takes, in order (a media whose wait goes on in the background after the interrupt would lose
   * the first of them).
   */
  @Test
  default void anInterruptedTakeLeavesEveryLaterValueForTheNextTake() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("interrupted", events);
      Reader<Integer> direct = source.reader();
      Reader<Integer> served = source.then(core.chain("copy", (Integer x) -> x)).reader();
      core.start();
      List<Caller> callers = new ArrayList<>();
      for (Reader<Integer> reader : List.of(direct, served)) {
        callers.add(new Caller("take", reader::take));
        callers.add(new Caller("take-timeout", () -> reader.take(Duration.ofHours(1))));
      }
      Caller.awaitBlocked(callers);
      long interrupted = System.nanoTime();
      for (Caller caller : callers) {
        caller.thread.interrupt();
      }
      for (Caller caller : callers) {
        assertInstanceOf(InterruptedException.class, caller.awaitFailure(patience()));
      }
      Duration took = Duration.ofNanos(System.nanoTime() - interrupted);
      assertTrue(
          took.compareTo(Duration.ofSeconds(3)) < 0,
          "the interrupted takes ended within about a second (3 s on a busy machine): " + took);
      for (int i = 1; i <= 3; i++) {
        events.publish(i);
      }
      assertEquals(List.of(1, 2, 3), takeOrFail(direct, 3), "the event source's reader");
      assertEquals(List.of(1, 2, 3), takeOrFail(served, 3), "the service output's reader");
    }
  }

  /**
   * {@link Reader}: "When the core is closed, blocked and later calls throw {@link
   * CoreClosedException}". A take and a timed take waiting on a reader of an event source and on
   * one of a service's output end with it when the core closes, within the kit's patience.
   */
  @Test
  default void takesWaitingWhenTheCoreClosesEndWithCoreClosedException()
      throws InterruptedException {
    PrimeCore core = newCore();
    List<Caller> callers = new ArrayList<>();
    try (core) {
      Source<Integer> source = core.source("quiet", new EventBlock<Integer>());
      Source<Integer> output = source.then(core.chain("quiet-copy", (Integer x) -> x));
      core.start();
      for (Source<Integer> waitedOn : List.of(source, output)) {
        Reader<Integer> untimed = waitedOn.reader();
        Reader<Integer> timed = waitedOn.reader();
        callers.add(new Caller(waitedOn.name() + "-take", untimed::take));
        callers.add(
            new Caller(waitedOn.name() + "-take-timeout", () -> timed.take(Duration.ofHours(1))));
      }
      Caller.awaitBlocked(callers);
    }
    for (Caller caller : callers) {
      assertInstanceOf(
          CoreClosedException.class, caller.awaitFailure(patience()), caller.thread.getName());
    }
    assertNoThreadsLeft(core);
  }

  /**
   * A block that interrupts its own thread (one that catches an {@code InterruptedException} and
   * restores the flag, as is customary) does not end the service it runs in: while the core is
   * open, a service clears that flag after the block returns and goes on with the next value,
   * whether it runs a chain linked to a source, a filter, a flat-map or a listener; only {@code
   * close()} ends a service. A synchronous call of such a block returns the block's value (on the
   * in-memory media the block ran on the caller's thread, whose flag it set: the caller sees it).
   */
  @Test
  default void aBlockThatInterruptsItsOwnThreadDoesNotEndItsService()
      throws InterruptedException {
    CountDownLatch heard = new CountDownLatch(1);
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("self-interrupting", events);
      Reader<Integer> mapped =
          source.then(core.chain("self-interrupt", (Integer x) -> interruptOn(1, x))).reader();
      Reader<Integer> passed = source.filter(x -> interruptOn(1, x) != null).reader();
      Reader<Integer> expanded = source.flatMap((Integer x) -> List.of(interruptOn(1, x))).reader();
      source.listen(
          x -> {
            interruptOn(1, x);
            if (x == 2) {
              heard.countDown();
            }
          });
      Block<Integer, Integer> called =
          core.chain("called-self-interrupt", (Integer x) -> interruptOn(1, x) * 10).toBlock();
      core.start();
      events.publish(1);
      events.publish(2);
      assertEquals(List.of(1, 2), takeOrFail(mapped, 2), "the chain's service went on");
      assertEquals(List.of(1, 2), takeOrFail(passed, 2), "the filter went on");
      assertEquals(List.of(1, 2), takeOrFail(expanded, 2), "the flat-map went on");
      assertTrue(
          heard.await(patience().toMillis(), TimeUnit.MILLISECONDS), "the listener went on");
      try {
        assertEquals(10, called.process(1), "a synchronous call returns the block's value");
        if (blocksRunOnTheCallersThread()) {
          assertTrue(Thread.currentThread().isInterrupted(), "the block ran on this thread");
        }
      } finally {
        Thread.interrupted(); // the flag the block set on this thread, where it ran here
      }
      assertEquals(20, called.process(2), "the chain works after the block interrupted itself");
    }
  }

  /**
   * The flag a block sets on its own thread is cleared after the block, so it does not fail what
   * the service does next with the block's output: a publish that waits for room in a full
   * service input (back-pressure) waits as for any block, and the value reaches that service in
   * its order; nothing goes to the error handler.
   */
  @Test
  default void aBlockThatInterruptsItsOwnThreadStillHasItsOutputPublishedToAFullInput()
      throws InterruptedException {
    int capacity = 2;
    List<Throwable> failures = new java.util.concurrent.CopyOnWriteArrayList<>();
    CoreConfig config =
        CoreConfig.builder()
            .publishTimeout(patience())
            .errorHandler((service, input, error) -> failures.add(error))
            .build();
    CountDownLatch inside = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    CountDownLatch lastTaken = new CountDownLatch(1);
    try (PrimeCore core = newCoreWithServiceInputCapacity(config, capacity)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> restless =
          core.source("in", events)
              .then(
                  core.chain(
                      "restless",
                      (Integer x) -> {
                        if (x == capacity + 1) {
                          lastTaken.countDown();
                        }
                        return interruptOn(x, x);
                      }));
      List<Integer> heard = new java.util.concurrent.CopyOnWriteArrayList<>();
      CountDownLatch all = new CountDownLatch(capacity + 2);
      restless
          .then(stuckChain(core, "slow", inside, release))
          .listen(
              x -> {
                heard.add(x);
                all.countDown();
              });
      core.start();
      fillStuckInput(events, inside, capacity); // 0 held by slow, 1 and 2 fill its input
      events.publish(capacity + 1); // restless's publish of it waits for room, its flag set
      assertTrue(lastTaken.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      awaitWaiting(core, "restless"); // its publish of 3 waits for room (or failed)
      release.countDown();
      assertTrue(all.await(patience().toMillis(), TimeUnit.MILLISECONDS), "heard only " + heard);
      assertEquals(List.of(0, 1, 2, 3), heard, "every value, in order");
      assertEquals(List.of(), failures, "nothing failed");
    } finally {
      release.countDown();
    }
  }

  /**
   * A synchronous call whose block hangs. Where blocks run on the caller's thread (Liberty,
   * Radiant) the block hangs that very thread: interrupting the caller reaches the block, and
   * what the block makes of it is what the caller gets (here the block fails, so a {@link
   * dev.prime.ChainFailedException} naming the chain), while {@code close()} cannot reach it.
   * Where chains are services (Optimus) the caller waits for a reply: interrupting it ends the wait
   * with a {@link PrimeException} and keeps its flag, and {@code close()} ends the wait of another
   * caller with {@link CoreClosedException}, within the kit's patience.
   */
  @Test
  default void aCallerOfAHangingBlockEndsByItsInterruptOrWhereItWaitsForAReplyByClose()
      throws InterruptedException {
    CountDownLatch release = new CountDownLatch(1);
    PrimeCore core = newCore(CoreConfig.builder().shutdownTimeout(Duration.ofMillis(500)).build());
    try {
      CountDownLatch entered = new CountDownLatch(1);
      Block<Integer, Integer> hanging =
          core.chain(
                  "hanging",
                  (Integer x) -> {
                    entered.countDown();
                    try {
                      release.await(patience().toMillis(), TimeUnit.MILLISECONDS);
                    } catch (InterruptedException e) {
                      throw new IllegalStateException("the hanging block was interrupted", e);
                    }
                    return x;
                  })
              .toBlock();
      core.start();
      Caller interrupted = new Caller("hanging-interrupted", () -> hanging.process(1));
      assertTrue(entered.await(patience().toMillis(), TimeUnit.MILLISECONDS), "the block runs");
      interrupted.thread.interrupt();
      Throwable ended = interrupted.awaitFailure(patience());
      if (blocksRunOnTheCallersThread()) {
        assertInstanceOf(dev.prime.ChainFailedException.class, ended, "what the block made of it");
        assertEquals("hanging", ((dev.prime.ChainFailedException) ended).chainName());
        return;
      }
      assertInstanceOf(PrimeException.class, ended, "the wait for the reply ended");
      assertTrue(interrupted.interruptedAtEnd, "the caller's interrupt flag stays set");
      Caller waiting = new Caller("hanging-closed", () -> hanging.process(2));
      assertFalse(
          waiting.ended.await(200, TimeUnit.MILLISECONDS), "the caller waits for the hanging block");
      core.close();
      assertInstanceOf(CoreClosedException.class, waiting.awaitFailure(patience()));
    } finally {
      release.countDown();
      core.close();
    }
  }

  /**
   * architecture.md (<i>Interrupts</i>): "while the core is open the service clears that flag
   * after the block and goes on with the next value". A chain's block and a listener that
   * interrupt their own threads on every value find the flag cleared when they get the next
   * one; nothing fails.
   */
  @Test
  default void aServiceClearsTheFlagItsBlockSetBeforeItsNextValue() throws InterruptedException {
    List<String> found = new java.util.concurrent.CopyOnWriteArrayList<>();
    List<Throwable> failures = new java.util.concurrent.CopyOnWriteArrayList<>();
    CountDownLatch heard = new CountDownLatch(3);
    CoreConfig config = failuresInto(failures);
    try (PrimeCore core = newCore(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("restless-values", events);
      Reader<Integer> out =
          source
              .then(
                  core.chain(
                      "restless-block",
                      (Integer x) -> {
                        if (Thread.currentThread().isInterrupted()) {
                          found.add("the block got " + x);
                        }
                        Thread.currentThread().interrupt();
                        return x;
                      }))
              .reader();
      source.listen(
          x -> {
            if (Thread.currentThread().isInterrupted()) {
              found.add("the listener got " + x);
            }
            Thread.currentThread().interrupt();
            heard.countDown();
          });
      core.start();
      for (int i = 1; i <= 3; i++) {
        events.publish(i);
      }
      assertEquals(List.of(1, 2, 3), takeOrFail(out, 3), "the service went on");
      assertTrue(heard.await(patience().toMillis(), TimeUnit.MILLISECONDS), "the listener went on");
      assertEquals(List.of(), found, "values whose block started with the flag set");
      assertEquals(List.of(), failures, "nothing failed");
    }
  }

  /**
   * architecture.md (<i>Interrupts</i>): in a service, the blocks run after one that interrupted
   * its own thread see the flag until the service clears it before its next value. The second
   * block of a linked chain sees it where the media runs the linked chain as one function on one
   * thread (Liberty, Radiant), and not where each chain is a service on a thread of its own
   * (Optimus); on every media the first block starts each value without it, and nothing fails.
   */
  @Test
  default void theNextBlockOfALinkedChainSeesTheFlagOnlyWhereTheChainIsOneFunction()
      throws InterruptedException {
    List<String> seen = new java.util.concurrent.CopyOnWriteArrayList<>();
    List<Throwable> failures = new java.util.concurrent.CopyOnWriteArrayList<>();
    CoreConfig config = failuresInto(failures);
    try (PrimeCore core = newCore(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      Chain<Integer, Integer> first =
          core.chain(
              "restless-first",
              (Integer x) -> {
                seen.add("first " + x + (Thread.currentThread().isInterrupted() ? " flagged" : ""));
                Thread.currentThread().interrupt();
                return x;
              });
      Chain<Integer, Integer> second =
          core.chain(
              "restless-second",
              (Integer x) -> {
                seen.add("second " + x + (Thread.currentThread().isInterrupted() ? " flagged" : ""));
                return x;
              });
      Reader<Integer> out =
          core.link(core.source("restless-link", events), core.link(first, second)).reader();
      core.start();
      events.publish(1);
      events.publish(2);
      assertEquals(List.of(1, 2), takeOrFail(out, 2), "the service went on");
      String second1 = blocksRunOnTheCallersThread() ? "second 1 flagged" : "second 1";
      String second2 = blocksRunOnTheCallersThread() ? "second 2 flagged" : "second 2";
      List<String> firsts = seen.stream().filter(line -> line.startsWith("first")).toList();
      List<String> seconds = seen.stream().filter(line -> line.startsWith("second")).toList();
      assertEquals(List.of("first 1", "first 2"), firsts, "each value's first block starts clean");
      assertEquals(List.of(second1, second2), seconds, "what the second block saw");
      assertEquals(List.of(), failures, "nothing failed");
    }
  }

  /**
   * architecture.md (<i>Interrupts</i>): in a service, the blocks run after one that interrupted
   * its own thread see the flag until the service clears it before its next value. Where a
   * template runs its parts on its own thread (Liberty, Radiant), a union's second part sees its
   * first part's flag, a for-each's second element the first's and the branch its condition's.
   * Where each part is a service of its own (Optimus), every part starts without it, and a
   * condition that sets it on the template's thread fails no call: the branch runs. On every media
   * each value's first part starts without the flag, nothing fails and the services go on with the
   * next value.
   */
  @Test
  default void theLaterPartsOfATemplateSeeTheFlagWhereTheyRunOnItsThread()
      throws InterruptedException {
    List<String> seen = new java.util.concurrent.CopyOnWriteArrayList<>();
    List<Throwable> failures = new java.util.concurrent.CopyOnWriteArrayList<>();
    CoreConfig config = failuresInto(failures);
    try (PrimeCore core = newCore(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("restless-parts", events);
      Reader<dev.prime.Tuple2<Integer, Integer>> unions =
          source
              .then(
                  core.union(
                      core.chain("union-first", (Integer x) -> flagging(seen, "union-first", x)),
                      core.chain("union-second", (Integer x) -> flagging(seen, "union-second", x))))
              .reader();
      Reader<Integer> branches =
          source
              .then(
                  core.ifThenElse(
                      (Integer x) -> x == 1 ? flagging(seen, "condition", x) > 0 : x > 0,
                      core.chain("then-branch", (Integer x) -> flagging(seen, "then-branch", x)),
                      core.chain("else-branch", (Integer x) -> flagging(seen, "else-branch", x))))
              .reader();
      Reader<List<Integer>> elements =
          source
              .then(core.chain("pair", (Integer x) -> List.of(10 * x, 10 * x + 1)))
              .then(core.forEach(core.chain("element", (Integer x) -> flagging(seen, "element", x))))
              .reader();
      core.start();
      events.publish(1);
      events.publish(2);
      boolean oneThread = blocksRunOnTheCallersThread();
      String later = oneThread ? " flagged" : "";
      assertEquals(
          List.of(new dev.prime.Tuple2<>(1, 1), new dev.prime.Tuple2<>(2, 2)),
          takeOrFail(unions, 2),
          "the union's service went on");
      assertEquals(
          List.of(List.of(10, 11), List.of(20, 21)),
          takeOrFail(elements, 2),
          "the for-each's service went on");
      assertEquals(
          List.of(1, 2),
          takeOrFail(branches, 2),
          "the if-then-else's service called the branch of each value");
      assertEquals(
          List.of(
              "union-first 1",
              "union-second 1" + later,
              "union-first 2",
              "union-second 2" + later),
          seen.stream().filter(line -> line.startsWith("union")).toList(),
          "what the union's parts saw");
      assertEquals(
          List.of("element 10", "element 11" + later, "element 20", "element 21" + later),
          seen.stream().filter(line -> line.startsWith("element")).toList(),
          "what the for-each's elements saw");
      List<String> branchLines =
          seen.stream().filter(line -> line.contains("branch")).distinct().sorted().toList();
      if (oneThread) {
        assertEquals(
            List.of("then-branch 1 flagged", "then-branch 2"),
            branchLines,
            "the branch sees its condition's flag, and the next value starts without it");
        assertEquals(List.of(), failures, "nothing failed");
      } else {
        assertEquals(
            List.of("then-branch 1", "then-branch 2"),
            branchLines,
            "each branch, a service of its own, starts without the flag");
        assertEquals(List.of(), failures, "nothing failed: the condition's flag fails no call");
      }
    }
  }

  /**
   * architecture.md (<i>Interrupts</i>): a block of a service that interrupted its own thread and
   * then calls a chain (its {@code toBlock()}) gets the chain's result on every media: on Liberty
   * and Radiant the called block runs inline, on Optimus the call is made as if the flag were not
   * set; the flag is set again after the call, and the service clears it before its next value.
   */
  @Test
  default void aBlockThatInterruptedItsThreadStillGetsTheResultOfAChainItCalls()
      throws InterruptedException {
    List<String> seen = new java.util.concurrent.CopyOnWriteArrayList<>();
    List<Throwable> failures = new java.util.concurrent.CopyOnWriteArrayList<>();
    CoreConfig config = failuresInto(failures);
    try (PrimeCore core = newCore(config)) {
      Block<Integer, Integer> callee = core.chain("callee", (Integer x) -> x + 1).toBlock();
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> results =
          core.source("restless-caller", events)
              .then(
                  core.chain(
                      "caller",
                      (Integer x) -> {
                        boolean flaggedBefore = Thread.currentThread().isInterrupted();
                        Thread.currentThread().interrupt();
                        Integer result = callee.process(x);
                        seen.add(
                            x
                                + (flaggedBefore ? " flagged before" : "")
                                + (Thread.currentThread().isInterrupted() ? " flagged after" : ""));
                        return result;
                      }))
              .reader();
      core.start();
      events.publish(1);
      events.publish(2);
      assertEquals(List.of(2, 3), takeOrFail(results, 2), "each value's call got its result");
      assertEquals(
          List.of("1 flagged after", "2 flagged after"),
          seen,
          "the flag stays set after the call, and the next value starts without it");
      assertEquals(List.of(), failures, "nothing failed");
    }
  }

  /**
   * architecture.md (<i>Interrupts</i>): the same holds when the chain the block calls is another
   * open core's (its {@code toBlock()}): on Liberty and Radiant the called block runs inline, on
   * Optimus the call is made as if the flag were not set, whichever open core the chain is of; the
   * flag is set again after the call, and the service clears it before its next value.
   */
  @Test
  default void aBlockThatInterruptedItsThreadStillGetsTheResultOfAnotherCoresChainItCalls()
      throws InterruptedException {
    List<String> seen = new java.util.concurrent.CopyOnWriteArrayList<>();
    List<Throwable> failures = new java.util.concurrent.CopyOnWriteArrayList<>();
    CoreConfig config = failuresInto(failures);
    try (PrimeCore other = newCore(config);
        PrimeCore core = newCore(config)) {
      Block<Integer, Integer> callee =
          other.chain("other-core-callee", (Integer x) -> x + 1).toBlock();
      other.start();
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> results =
          core.source("restless-cross-caller", events)
              .then(
                  core.chain(
                      "cross-caller",
                      (Integer x) -> {
                        boolean flaggedBefore = Thread.currentThread().isInterrupted();
                        Thread.currentThread().interrupt();
                        Integer result = callee.process(x);
                        seen.add(
                            x
                                + (flaggedBefore ? " flagged before" : "")
                                + (Thread.currentThread().isInterrupted() ? " flagged after" : ""));
                        return result;
                      }))
              .reader();
      core.start();
      events.publish(1);
      events.publish(2);
      assertEquals(
          List.of(2, 3), takeOrFail(results, 2), "each value's call to the other core got its result");
      assertEquals(
          List.of("1 flagged after", "2 flagged after"),
          seen,
          "the flag stays set after the call, and the next value starts without it");
      assertEquals(List.of(), failures, "nothing failed");
    }
  }

  /**
   * architecture.md (<i>Interrupts</i>, <i>Lifecycle</i>): a close of a core whose service's block
   * waits interruptibly (here on a latch that never opens) interrupts the block at once and returns
   * as soon as the block ends on it, not after {@code shutdownTimeout} (here three times the kit's
   * patience): on Optimus too, whose connections are closed by then, so nothing the block returns
   * could be stored.
   */
  @Test
  default void aCloseInterruptsAServicesWaitingBlockWithoutWaitingForTheShutdownTimeout()
      throws InterruptedException {
    CountDownLatch inside = new CountDownLatch(1);
    CountDownLatch never = new CountDownLatch(1);
    CountDownLatch sawInterrupt = new CountDownLatch(1);
    CoreConfig config =
        CoreConfig.builder().shutdownTimeout(patience().multipliedBy(3)).build();
    PrimeCore core = newCore(config);
    try {
      EventBlock<Integer> events = new EventBlock<>();
      core.source("waiting-block-events", events)
          .then(
              core.chain(
                  "waiting-block",
                  (Integer x) -> {
                    inside.countDown();
                    try {
                      never.await(patience().toMillis() * 4, TimeUnit.MILLISECONDS);
                    } catch (InterruptedException e) {
                      sawInterrupt.countDown();
                      Thread.currentThread().interrupt();
                    }
                    return x;
                  }))
          .reader();
      core.start();
      events.publish(1);
      assertTrue(
          inside.await(patience().toMillis(), TimeUnit.MILLISECONDS), "the service's block runs");
      assertClosedWithinPatience(core, config, "waited interruptibly");
      assertTrue(
          sawInterrupt.await(patience().toMillis(), TimeUnit.MILLISECONDS),
          "the block's wait ended on an interrupt");
    } finally {
      never.countDown();
      core.close();
    }
  }

  /**
   * architecture.md (<i>Interrupts</i>, <i>Lifecycle</i>): a close of a core whose service's block
   * is in a call of another core's chain, whose block waits (interruptibly), ends that call at
   * once, not after {@code shutdownTimeout}: on Liberty and Radiant the called block runs inline,
   * on the service's thread that the close interrupts; on Optimus the close interrupts the
   * service's wait for the other core's reply. The close returns long before {@code
   * shutdownTimeout} (here three times the kit's patience).
   */
  @Test
  default void aCloseEndsAServicesCallOfAnotherCoresChainWithoutWaitingForTheShutdownTimeout()
      throws InterruptedException {
    CountDownLatch inside = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    CoreConfig config =
        CoreConfig.builder().shutdownTimeout(patience().multipliedBy(3)).build();
    PrimeCore other = newCore(config);
    PrimeCore core = newCore(config);
    try {
      Block<Integer, Integer> waiting =
          other
              .chain("other-core-waiting", (Integer x) -> waitUntilReleased(inside, release, x))
              .toBlock();
      other.start();
      assertACloseEndsAServicesCall(
          core, config, waiting, inside, "a call of another core's chain");
    } finally {
      release.countDown();
      core.close();
      other.close();
    }
  }

  /**
   * As above, the other core's chain isolated ({@link PrimeCore#isolate}) and called through a
   * user's {@code toBlock()}: the close ends the service's call at once, on Optimus too, where the
   * call of an isolated chain also waits for the other core's reply.
   */
  @Test
  default void aCloseEndsAServicesCallOfAnotherCoresIsolatedChainWithoutWaitingForTheShutdownTimeout()
      throws InterruptedException {
    assertACloseEndsAServicesCallOfAnotherCoresIsolatedChain(false);
  }

  /**
   * As above, the service's call waiting for its turn (the isolated chain's block runs another
   * user's call, which waits): a call waiting for its turn ends when its caller is interrupted
   * ({@link PrimeCore#isolate}), so the close ends it at once too.
   */
  @Test
  default void aCloseEndsAServicesWaitForItsTurnInAnotherCoresIsolatedChainWithoutWaitingForTheShutdownTimeout()
      throws InterruptedException {
    assertACloseEndsAServicesCallOfAnotherCoresIsolatedChain(true);
  }

  /**
   * A service of a core calls, through a user of another core's isolated chain, the chain whose
   * block waits; {@code behindAnotherCall}: another user's call runs the block first, so the
   * service's call waits for its turn. The close of the service's core returns within the kit's
   * patience, though its {@code shutdownTimeout} is three times that.
   */
  private void assertACloseEndsAServicesCallOfAnotherCoresIsolatedChain(boolean behindAnotherCall)
      throws InterruptedException {
    CountDownLatch inside = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    CoreConfig config =
        CoreConfig.builder().shutdownTimeout(patience().multipliedBy(3)).build();
    PrimeCore other = newCore(config);
    PrimeCore core = newCore(config);
    Thread first = null;
    try {
      Isolated<Integer, Integer> isolated =
          other.isolate(
              other.chain(
                  "other-core-isolated", (Integer x) -> waitUntilReleased(inside, release, x)));
      Block<Integer, Integer> firstUser = isolated.newUser().toBlock();
      Block<Integer, Integer> serviceUser = isolated.newUser().toBlock();
      other.start();
      if (behindAnotherCall) {
        first =
            new Thread(
                () -> {
                  try {
                    firstUser.process(0);
                  } catch (RuntimeException e) {
                    // ended by the other core's close at the end of the test: not what is checked
                  }
                },
                "isolated-first-caller");
        first.setDaemon(true);
        first.start();
        assertTrue(
            inside.await(patience().toMillis(), TimeUnit.MILLISECONDS),
            "the first user's call runs the isolated chain's block");
      }
      assertACloseEndsAServicesCall(
          core,
          config,
          serviceUser,
          behindAnotherCall ? null : inside,
          "a call of another core's isolated chain"
              + (behindAnotherCall ? ", waiting for its turn" : ""));
    } finally {
      release.countDown();
      core.close();
      other.close();
      if (first != null) {
        first.join(patience().toMillis());
      }
    }
  }

  /**
   * As above, the service's block calling another core's sync collector ({@link
   * PrimeCore#syncCollector}) of a source nothing is published to: the close ends the service's
   * wait for a value at once.
   */
  @Test
  default void aCloseEndsAServicesCallOfAnotherCoresCollectorWithoutWaitingForTheShutdownTimeout()
      throws InterruptedException {
    CoreConfig config =
        CoreConfig.builder().shutdownTimeout(patience().multipliedBy(3)).build();
    PrimeCore other = newCore(config);
    PrimeCore core = newCore(config);
    try {
      Block<Token, Integer> collect =
          other.syncCollector(other.source("other-core-silent", new EventBlock<Integer>())).toBlock();
      other.start();
      assertACloseEndsAServicesCall(
          core, config, x -> collect.process(Token.INSTANCE), null, "a call of another core's collector");
    } finally {
      core.close();
      other.close();
    }
  }

  /**
   * As above, the service's block calling another core's repeater whose round's block waits: the
   * close ends the service's call at once.
   */
  @Test
  default void aCloseEndsAServicesCallOfAnotherCoresRepeaterWithoutWaitingForTheShutdownTimeout()
      throws InterruptedException {
    CountDownLatch inside = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    CoreConfig config =
        CoreConfig.builder().shutdownTimeout(patience().multipliedBy(3)).build();
    PrimeCore other = newCore(config);
    PrimeCore core = newCore(config);
    try {
      Block<Integer, Integer> repeater =
          other
              .repeater(
                  other.chain(
                      "other-core-round",
                      (Integer x) -> waitUntilReleased(inside, release, x) + 1),
                  (Integer in, Integer out, List<Void> none) -> Repeat.stop(out))
              .toBlock();
      other.start();
      assertACloseEndsAServicesCall(
          core, config, repeater, inside, "a call of another core's repeater");
    } finally {
      release.countDown();
      core.close();
      other.close();
    }
  }

  /**
   * Declares on {@code core} (not started) a service whose block calls {@code callee}, starts it,
   * gives the service a value, waits for {@code started} (the callee's block runs; {@code null}:
   * the service's block is about to call) and checks that {@code core.close()} returns within the
   * kit's patience, well before its {@code shutdownTimeout}.
   */
  private void assertACloseEndsAServicesCall(
      PrimeCore core,
      CoreConfig config,
      Block<Integer, Integer> callee,
      CountDownLatch started,
      String what)
      throws InterruptedException {
    CountDownLatch calling = new CountDownLatch(1);
    EventBlock<Integer> events = new EventBlock<>();
    core.source("closing-caller-events", events)
        .then(
            core.chain(
                "closing-caller",
                (Integer x) -> {
                  calling.countDown();
                  return callee.process(x);
                }))
        .reader();
    core.start();
    events.publish(1);
    assertTrue(
        (started == null ? calling : started).await(patience().toMillis(), TimeUnit.MILLISECONDS),
        started == null ? "the service makes " + what : "the called block runs in " + what);
    assertClosedWithinPatience(core, config, "was in " + what);
  }

  /**
   * Closes {@code core} on a thread of its own and checks that {@code close()} returns within the
   * kit's patience, well before {@code config}'s {@code shutdownTimeout}, though its service's
   * block {@code what} ("was in a call of ...", "waited interruptibly").
   */
  private void assertClosedWithinPatience(PrimeCore core, CoreConfig config, String what)
      throws InterruptedException {
    CountDownLatch closed = new CountDownLatch(1);
    Thread closer =
        new Thread(
            () -> {
              core.close();
              closed.countDown();
            },
            "closing-caller-closer");
    closer.setDaemon(true);
    closer.start();
    assertTrue(
        closed.await(patience().toMillis(), TimeUnit.MILLISECONDS),
        "close() returned within "
            + patience()
            + ", though its service's block "
            + what
            + " (shutdownTimeout "
            + config.shutdownTimeout()
            + ")");
  }

  /**
   * A block's body that says it runs ({@code inside}), waits (interruptibly, at most four times
   * the kit's patience) until {@code release} opens, keeps an interrupt's flag and returns {@code
   * x}.
   */
  private Integer waitUntilReleased(CountDownLatch inside, CountDownLatch release, Integer x) {
    inside.countDown();
    try {
      release.await(patience().toMillis() * 4, TimeUnit.MILLISECONDS);
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
    }
    return x;
  }

  /** A configuration whose error handler adds every failure it gets to {@code failures}. */
  private static CoreConfig failuresInto(List<Throwable> failures) {
    return CoreConfig.builder().errorHandler((service, input, error) -> failures.add(error)).build();
  }

  /**
   * Notes in {@code seen} that {@code part} got {@code x}, and whether its thread's flag was set
   * then, and interrupts its own thread; returns {@code x}.
   */
  private static Integer flagging(List<String> seen, String part, Integer x) {
    seen.add(part + " " + x + (Thread.currentThread().isInterrupted() ? " flagged" : ""));
    Thread.currentThread().interrupt();
    return x;
  }

  /** Interrupts the calling thread when {@code x} is {@code on}; returns {@code x}. */
  private static Integer interruptOn(int on, Integer x) {
    if (x == on) {
      Thread.currentThread().interrupt();
    }
    return x;
  }

  @Test
  default void aListenerCanCloseItsOwnCore() throws InterruptedException {
    closeFromAService((core, events, close) -> core.source(events).listen(x -> close.run()));
  }

  @Test
  default void aChainLinkedToASourceCanCloseItsOwnCore() throws InterruptedException {
    closeFromAService(
        (core, events, close) ->
            core.link(
                core.source(events),
                core.chain(
                    "closer",
                    x -> {
                      close.run();
                      return x;
                    })));
  }

  /**
   * A block called synchronously may close its own core: {@code close()} returns within the
   * kit's patience (also where the block runs on a service's thread, which it then cannot wait
   * for), the caller gets the block's value (where the block ran on its own thread) or {@link
   * CoreClosedException}, never a hang, and the core leaves no thread.
   */
  @Test
  default void aBlockCalledSynchronouslyCanCloseItsOwnCore() throws InterruptedException {
    CoreConfig config = CoreConfig.builder().shutdownTimeout(patience().multipliedBy(3)).build();
    PrimeCore core = newCore(config);
    CountDownLatch closeReturned = new CountDownLatch(1);
    AtomicReference<Throwable> closeFailed = new AtomicReference<>();
    Caller caller;
    try (core) {
      Block<Integer, Integer> closing =
          core.chain(
                  "self-closing",
                  (Integer x) -> {
                    try {
                      core.close();
                    } catch (Throwable t) {
                      closeFailed.set(t);
                    }
                    closeReturned.countDown();
                    return x + 1;
                  })
              .toBlock();
      core.start();
      AtomicReference<Integer> result = new AtomicReference<>();
      caller = new Caller("self-closing", () -> result.set(closing.process(1)));
      assertTrue(
          closeReturned.await(patience().toMillis(), TimeUnit.MILLISECONDS),
          "close() called from the block did not return within " + patience());
      Throwable ended = caller.awaitFailure(patience());
      if (ended == null) {
        assertEquals(2, result.get(), "the caller got the block's value");
      } else {
        assertInstanceOf(CoreClosedException.class, ended, "or CoreClosedException");
      }
    }
    if (closeFailed.get() != null) {
      throw new AssertionError("close() from the block threw", closeFailed.get());
    }
    awaitNoThreadsLeft(core);
  }

  /** How a test declares a service that runs {@code close} when it gets a value. */
  @FunctionalInterface
  interface ClosingService {
    void declare(PrimeCore core, EventBlock<Integer> events, Runnable close);
  }

  /**
   * Declares a service that closes its own core, next to another service, with a shutdown
   * timeout far above the kit's patience: a close that waited for its own thread would take that
   * long. The close must return within the patience and leave no thread.
   */
  private void closeFromAService(ClosingService service) throws InterruptedException {
    CoreConfig config = CoreConfig.builder().shutdownTimeout(patience().multipliedBy(3)).build();
    PrimeCore core = newCore(config);
    EventBlock<Integer> events = new EventBlock<>();
    // What the core logs meanwhile, with a binding that writes to System.err (slf4j-simple, as in
    // the project's tests): a close that could not stop its own thread says so there.
    java.io.PrintStream stderr = System.err;
    java.io.ByteArrayOutputStream logged = new java.io.ByteArrayOutputStream();
    System.setErr(new java.io.PrintStream(new TeeStream(stderr, logged), true));
    CountDownLatch closeReturned = new CountDownLatch(1);
    AtomicReference<Thread> closer = new AtomicReference<>();
    AtomicReference<Throwable> closeFailed = new AtomicReference<>();
    try (core) {
      service.declare(
          core,
          events,
          () -> {
            closer.set(Thread.currentThread());
            try {
              core.close();
            } catch (Throwable t) {
              closeFailed.set(t);
            }
            closeReturned.countDown();
          });
      core.source(events).listen(x -> {}); // another service, which the closing one stops
      core.start();
      events.publish(1);
      assertTrue(
          closeReturned.await(patience().toMillis(), TimeUnit.MILLISECONDS),
          "close() called from a service's thread did not return within " + patience());
    } finally {
      System.setErr(stderr);
    }
    if (closeFailed.get() != null) {
      throw new AssertionError("close() from a service thread threw", closeFailed.get());
    }
    closer.get().join(patience().toMillis());
    assertFalse(closer.get().isAlive(), "the service that closed its core ended");
    assertNoThreadsLeft(core);
    String log = logged.toString(java.nio.charset.StandardCharsets.UTF_8);
    for (String complaint : List.of("abandoned", "still running")) {
      assertFalse(log.contains(complaint), "the core complained while closing itself:\n" + log);
    }
  }

  /** Writes to two streams. */
  final class TeeStream extends java.io.OutputStream {
    private final java.io.OutputStream first;
    private final java.io.OutputStream second;

    TeeStream(java.io.OutputStream first, java.io.OutputStream second) {
      this.first = first;
      this.second = second;
    }

    @Override
    public synchronized void write(int b) throws java.io.IOException {
      first.write(b);
      second.write(b);
    }

    @Override
    public synchronized void write(byte[] b, int off, int len) throws java.io.IOException {
      first.write(b, off, len);
      second.write(b, off, len);
    }
  }

  /**
   * An isolated identity chain whose block, given 1, counts {@code entered} down and then holds
   * the chain until {@code release} (at most the kit's patience).
   */
  /**
   * Waits until {@code waiting}, a call of an isolated chain that another caller holds, waits for
   * its turn: on a media whose blocks run on the caller's thread, until that thread blocks (bounded
   * by the kit's patience); on another (the isolated block runs on a service thread this test
   * cannot see, and the caller's thread waits for the reply), half a second, in which the call
   * reaches the service that waits for the isolated chain, and must not end.
   */
  private void awaitItsTurn(Caller waiting) throws InterruptedException {
    if (blocksRunOnTheCallersThread()) {
      long deadline = System.nanoTime() + patience().toNanos();
      while (waiting.ended.getCount() > 0
          && waiting.thread.getState() != Thread.State.WAITING
          && waiting.thread.getState() != Thread.State.TIMED_WAITING
          && System.nanoTime() < deadline) {
        Thread.onSpinWait(); // until the waiter blocks (bounded by the kit's patience)
      }
    } else {
      assertFalse(
          waiting.ended.await(500, TimeUnit.MILLISECONDS),
          "the waiter waits while the holder holds the isolated chain");
    }
  }

  private Isolated<Integer, Integer> holdingIsolate(
      PrimeCore core, CountDownLatch entered, CountDownLatch release) {
    return holdingIsolate(core, entered, release, new CountDownLatch(1));
  }

  /** Like the isolate above; given 2, it also counts {@code ranFor2} down. */
  private Isolated<Integer, Integer> holdingIsolate(
      PrimeCore core, CountDownLatch entered, CountDownLatch release, CountDownLatch ranFor2) {
    return holdingIsolate(
        core,
        1,
        entered,
        release,
        x -> {
          if (x == 2) {
            ranFor2.countDown();
          }
        });
  }

  /**
   * An isolated chain that tells {@code ran} of each input and, given {@code held}, counts {@code
   * entered} down and holds until {@code release} (bounded by the kit's patience).
   */
  private Isolated<Integer, Integer> holdingIsolate(
      PrimeCore core,
      int held,
      CountDownLatch entered,
      CountDownLatch release,
      java.util.function.IntConsumer ran) {
    return core.isolate(
        core.chain(
            (Integer x) -> {
              ran.accept(x);
              if (x == held) {
                entered.countDown();
                try {
                  release.await(patience().toMillis(), TimeUnit.MILLISECONDS);
                } catch (InterruptedException e) {
                  Thread.currentThread().interrupt();
                }
              }
              return x;
            }));
  }
}

package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.atomic.AtomicInteger;
import org.junit.jupiter.api.Test;

/** The logic-layer template blocks on their own, without any core. */
class LogicBlocksTest {

  @Test
  void linkAppliesFirstThenSecond() {
    Block<Integer, String> block = new LinkBlock<>(x -> x + 1, x -> "v" + x);
    assertEquals("v3", block.process(2));
  }

  @Test
  void ifThenElseEvaluatesOnlyTheChosenBranch() {
    AtomicInteger otherwiseCalls = new AtomicInteger();
    Block<Integer, String> block =
        new IfThenElseBlock<>(
            x -> x > 0,
            x -> "then",
            x -> {
              otherwiseCalls.incrementAndGet();
              return "else";
            });
    assertEquals("then", block.process(1));
    assertEquals(0, otherwiseCalls.get());
    assertEquals("else", block.process(0));
    assertEquals(1, otherwiseCalls.get());
  }

  @Test
  void forEachKeepsOrderAndNullElements() {
    Block<List<Integer>, List<Integer>> block = new ForEachBlock<>(x -> x == 0 ? null : x * 2);
    List<Integer> expected = new ArrayList<>();
    expected.add(2);
    expected.add(null);
    expected.add(6);
    assertEquals(expected, block.process(List.of(1, 0, 3)));
    NullPointerException e = assertThrows(NullPointerException.class, () -> block.process(null));
    assertTrue(e.getMessage().contains("for-each"), e.getMessage());
  }

  @Test
  void unionCallsEveryPartInOrderWithTheSameInput() {
    List<String> calls = new ArrayList<>();
    Block<Integer, Tuple5<Integer, Integer, Integer, Integer, Integer>> five =
        UnionBlock.of(
            x -> {
              calls.add("a");
              return x;
            },
            x -> {
              calls.add("b");
              return x + 1;
            },
            x -> {
              calls.add("c");
              return x + 2;
            },
            x -> {
              calls.add("d");
              return x + 3;
            },
            x -> {
              calls.add("e");
              return x + 4;
            });
    assertEquals(new Tuple5<>(10, 11, 12, 13, 14), five.process(10));
    assertEquals(List.of("a", "b", "c", "d", "e"), calls);
    Block<Integer, Tuple2<Integer, String>> two = UnionBlock.of(x -> x, x -> "s");
    assertEquals(new Tuple2<>(1, "s"), two.process(1));
    Block<Integer, Tuple3<Integer, Integer, Integer>> three = UnionBlock.of(x -> x, x -> x, x -> x);
    assertEquals(new Tuple3<>(1, 1, 1), three.process(1));
    Block<Integer, Tuple4<Integer, Integer, Integer, Integer>> four =
        UnionBlock.of(x -> x, x -> x, x -> x, x -> -x);
    assertEquals(new Tuple4<>(1, 1, 1, -1), four.process(1));
    Block<Integer, Integer> none = null;
    NullPointerException e =
        assertThrows(NullPointerException.class, () -> UnionBlock.of(x -> x, none));
    assertTrue(e.getMessage().contains("2"), e.getMessage());
  }

  @Test
  void forkPublishesNonNullOutputs() {
    EventBlock<Integer> events = new EventBlock<>();
    List<Integer> published = new ArrayList<>();
    events.subscribe(published::add);
    Block<Integer, Integer> block = new ForkBlock<>(x -> x < 0 ? null : x, events);
    assertEquals(1, block.process(1));
    assertNull(block.process(-1));
    assertEquals(List.of(1), published);
  }

  @Test
  void guardUsesTheSubstituteWhenThePredicateFails() {
    Block<Integer, Integer> block = new GuardBlock<>(x -> x != 0, x -> 10 / x, x -> 0);
    assertEquals(5, block.process(2));
    assertEquals(0, block.process(0));
  }

  @Test
  void isolateReleasesItsLockWhenTheBlockThrows() {
    RuntimeException boom = new IllegalStateException("boom");
    Block<Integer, Integer> block =
        new IsolateBlock<>(
            x -> {
              if (x < 0) {
                throw boom;
              }
              return x;
            });
    assertSame(boom, assertThrows(IllegalStateException.class, () -> block.process(-1)));
    assertEquals(3, block.process(3));
  }

  @Test
  void repeaterLoopsAndPassesCollectedValues() {
    List<List<String>> collectedSeen = new ArrayList<>();
    AtomicInteger collectorCalls = new AtomicInteger();
    Block<Token, List<String>> collector =
        t -> List.of("c" + collectorCalls.incrementAndGet());
    Block<Integer, String> block =
        new RepeaterLoopBlock<Integer, Integer, String, String>(
            x -> x + 1,
            collector,
            (in, out, collected) -> {
              collectedSeen.add(collected);
              return out < 3 ? Repeat.again(out) : Repeat.stop("r" + out);
            });
    assertEquals("r3", block.process(0));
    assertEquals(List.of(List.of("c1"), List.of("c2"), List.of("c3")), collectedSeen);
  }

  @Test
  void repeaterWithoutCollectorSeesEmptyListsAndRejectsNullDecisions() {
    Block<Integer, Integer> stopAtOnce =
        new RepeaterLoopBlock<Integer, Integer, Void, Integer>(
            x -> x, null, (in, out, collected) -> Repeat.stop(collected.size()));
    assertEquals(0, stopAtOnce.process(1));
    Block<Integer, Integer> broken =
        new RepeaterLoopBlock<Integer, Integer, Void, Integer>(x -> x, null, (in, out, c) -> null);
    NullPointerException e = assertThrows(NullPointerException.class, () -> broken.process(1));
    assertTrue(e.getMessage().contains("Repeat.stop"), e.getMessage());
  }

  @Test
  void repeaterStopsWhenItsOwnersCheckThrowsOrItsThreadIsInterrupted() {
    AtomicInteger rounds = new AtomicInteger();
    Block<Integer, Integer> stoppedByOwner =
        new RepeaterLoopBlock<Integer, Integer, Void, Integer>(
            x -> rounds.incrementAndGet(),
            null,
            (in, out, c) -> Repeat.again(out),
            () -> {
              if (rounds.get() == 5) {
                throw new IllegalStateException("closed");
              }
            },
            () -> false);
    assertEquals("closed", assertThrows(IllegalStateException.class, () -> stoppedByOwner.process(0)).getMessage());
    assertEquals(5, rounds.get(), "the check runs between every two rounds");

    AtomicInteger more = new AtomicInteger();
    Block<Integer, Integer> interrupted =
        new RepeaterLoopBlock<Integer, Integer, Void, Integer>(
            x -> {
              if (more.incrementAndGet() == 3) {
                Thread.currentThread().interrupt();
              }
              return x;
            },
            null,
            (in, out, c) -> Repeat.again(out));
    try {
      assertThrows(PrimeException.class, () -> interrupted.process(0));
      assertEquals(3, more.get());
      assertTrue(Thread.currentThread().isInterrupted(), "the interrupt flag stays set");
    } finally {
      Thread.interrupted();
    }
  }

  @Test
  void repeaterStopsWhenItsCallerGaveUpAskingAtMostEveryFiftyMilliseconds() {
    AtomicInteger rounds = new AtomicInteger();
    AtomicInteger asked = new AtomicInteger();
    long started = System.nanoTime();
    Block<Integer, Integer> abandoned =
        new RepeaterLoopBlock<Integer, Integer, Void, Integer>(
            x -> rounds.incrementAndGet(),
            null,
            (in, out, c) -> Repeat.again(out),
            () -> {},
            () -> asked.incrementAndGet() == 2);
    PrimeException e = assertThrows(PrimeException.class, () -> abandoned.process(0));
    long tookMillis = (System.nanoTime() - started) / 1_000_000;
    assertTrue(e.getMessage().contains("gave up"), e.getMessage());
    assertEquals(2, asked.get(), "asked until the caller gave up");
    assertTrue(tookMillis >= 100, "asked at most once every 50 ms: two asks after " + tookMillis + " ms");
    assertTrue(rounds.get() > 2, "rounds run between the asks: " + rounds.get());
  }

  @Test
  void anInterruptedCallerDoesNotWaitForAnIsolatedBlock() throws InterruptedException {
    java.util.concurrent.CountDownLatch inside = new java.util.concurrent.CountDownLatch(1);
    java.util.concurrent.CountDownLatch release = new java.util.concurrent.CountDownLatch(1);
    List<Integer> ran = java.util.Collections.synchronizedList(new ArrayList<>());
    Block<Integer, Integer> isolated = new IsolateBlock<>(holdingAt(1, ran, inside, release));
    Thread holder = new Thread(() -> isolated.process(1));
    holder.start();
    try {
      assertTrue(inside.await(20, java.util.concurrent.TimeUnit.SECONDS));
      Thread.currentThread().interrupt();
      assertThrows(PrimeException.class, () -> isolated.process(2));
      assertTrue(Thread.interrupted(), "the interrupt flag stays set");
      assertEquals(List.of(1), ran, "the block did not run for the interrupted caller");
    } finally {
      release.countDown();
      holder.join(20_000);
    }
  }

  @Test
  void aCallWhoseCallerGaveUpIsNotRunAndAFreeLockAsksNothing() throws InterruptedException {
    java.util.concurrent.CountDownLatch inside = new java.util.concurrent.CountDownLatch(1);
    java.util.concurrent.CountDownLatch release = new java.util.concurrent.CountDownLatch(1);
    java.util.concurrent.atomic.AtomicBoolean gaveUp = new java.util.concurrent.atomic.AtomicBoolean();
    AtomicInteger asked = new AtomicInteger();
    List<Integer> ran = java.util.Collections.synchronizedList(new ArrayList<>());
    Block<Integer, Integer> isolated =
        new IsolateBlock<>(
            holdingAt(1, ran, inside, release),
            () -> {},
            () -> {
              asked.incrementAndGet();
              return gaveUp.get();
            });
    assertEquals(0, isolated.process(0));
    assertEquals(0, asked.get(), "a call that found the lock free is not asked about its caller");
    Thread holder = new Thread(() -> isolated.process(1));
    holder.start();
    java.util.concurrent.atomic.AtomicReference<Throwable> waiterFailure =
        new java.util.concurrent.atomic.AtomicReference<>();
    java.util.concurrent.CountDownLatch waiterEnded = new java.util.concurrent.CountDownLatch(1);
    try {
      assertTrue(inside.await(20, java.util.concurrent.TimeUnit.SECONDS));
      Thread waiter =
          new Thread(
              () -> {
                try {
                  isolated.process(2);
                } catch (Throwable t) {
                  waiterFailure.set(t);
                } finally {
                  waiterEnded.countDown();
                }
              });
      waiter.start();
      long deadline = System.nanoTime() + java.util.concurrent.TimeUnit.SECONDS.toNanos(20);
      while (asked.get() == 0 && System.nanoTime() < deadline) {
        Thread.onSpinWait(); // until the waiter asked once while waiting (bounded)
      }
      assertTrue(asked.get() > 0, "a waiting call asks about its caller while it waits");
      gaveUp.set(true);
      assertTrue(
          waiterEnded.await(5, java.util.concurrent.TimeUnit.SECONDS),
          "a call whose caller gave up stops waiting while the lock is still held");
      assertTrue(waiterFailure.get() instanceof PrimeException, String.valueOf(waiterFailure.get()));
      assertTrue(waiterFailure.get().getMessage().contains("gave up"), waiterFailure.get().getMessage());
    } finally {
      release.countDown();
      holder.join(20_000);
    }
    assertEquals(List.of(0, 1), ran, "the block did not run for the call whose caller gave up");
  }

  /**
   * A waiter whose turn comes while it is deciding to give up passes the turn on: the caller
   * behind it runs (without the hand-off it would wait for ever).
   */
  @Test
  void aWaiterThatGivesUpAsItsTurnComesPassesTheTurnOn() throws InterruptedException {
    java.util.concurrent.CountDownLatch release = new java.util.concurrent.CountDownLatch(1);
    java.util.concurrent.CountDownLatch inside = new java.util.concurrent.CountDownLatch(1);
    java.util.concurrent.CountDownLatch deciding = new java.util.concurrent.CountDownLatch(1);
    java.util.concurrent.CountDownLatch thirdEnded = new java.util.concurrent.CountDownLatch(1);
    List<Integer> ran = java.util.Collections.synchronizedList(new ArrayList<>());
    Thread[] holder = new Thread[1];
    Thread[] second = new Thread[1];
    Block<Integer, Integer> isolated =
        new IsolateBlock<>(
            holdingAt(0, ran, inside, release),
            () -> {},
            () -> {
              if (Thread.currentThread() != second[0]) {
                return false;
              }
              deciding.countDown();
              try {
                holder[0].join(20_000); // the holder's turn has ended: the second caller's has come
              } catch (InterruptedException e) {
                Thread.currentThread().interrupt();
              }
              return true;
            });
    holder[0] = new Thread(() -> isolated.process(0));
    holder[0].start();
    assertTrue(inside.await(20, java.util.concurrent.TimeUnit.SECONDS));
    java.util.concurrent.atomic.AtomicReference<Throwable> secondFailure =
        new java.util.concurrent.atomic.AtomicReference<>();
    second[0] =
        new Thread(
            () -> {
              try {
                isolated.process(1);
              } catch (Throwable t) {
                secondFailure.set(t);
              }
            });
    second[0].start();
    Thread third = null;
    try {
      assertTrue(deciding.await(20, java.util.concurrent.TimeUnit.SECONDS));
      third =
          new Thread(
              () -> {
                isolated.process(2);
                thirdEnded.countDown();
              });
      third.start();
      long deadline = System.nanoTime() + java.util.concurrent.TimeUnit.SECONDS.toNanos(20);
      while (third.getState() != Thread.State.TIMED_WAITING && System.nanoTime() < deadline) {
        Thread.onSpinWait(); // until the third caller waits for its turn (bounded)
      }
    } finally {
      release.countDown();
    }
    assertTrue(
        thirdEnded.await(5, java.util.concurrent.TimeUnit.SECONDS),
        "the caller behind one that gave up as its turn came got the turn");
    second[0].join(20_000);
    third.join(20_000);
    assertTrue(secondFailure.get() instanceof PrimeException, String.valueOf(secondFailure.get()));
    assertEquals(List.of(0, 2), ran);
  }

  /**
   * A block that records each input in {@code ran} and, given {@code held}, counts {@code inside}
   * down and holds until {@code release} (at most 20 s).
   */
  private static Block<Integer, Integer> holdingAt(
      int held,
      List<Integer> ran,
      java.util.concurrent.CountDownLatch inside,
      java.util.concurrent.CountDownLatch release) {
    return x -> {
      ran.add(x);
      if (x == held) {
        inside.countDown();
        try {
          release.await(20, java.util.concurrent.TimeUnit.SECONDS);
        } catch (InterruptedException e) {
          Thread.currentThread().interrupt();
        }
      }
      return x;
    };
  }

  @Test
  void repeatValues() {
    assertEquals(Repeat.again(1), Repeat.again(1));
    assertEquals(Repeat.stop("x"), Repeat.stop("x"));
    assertTrue(Repeat.again(1).isAgain());
    assertEquals("Repeat.stop(x)", Repeat.stop("x").toString());
  }

  @Test
  void constructorsRefuseNulls() {
    Block<Integer, Integer> id = x -> x;
    assertThrows(NullPointerException.class, () -> new LinkBlock<Integer, Integer, Integer>(null, id));
    assertThrows(NullPointerException.class, () -> new IfThenElseBlock<Integer, Integer>(null, id, id));
    assertThrows(NullPointerException.class, () -> new ForEachBlock<Integer, Integer>(null));
    assertThrows(NullPointerException.class, () -> new ForkBlock<Integer, Integer>(id, null));
    assertThrows(NullPointerException.class, () -> new GuardBlock<Integer, Integer>(x -> true, null, id));
    assertThrows(NullPointerException.class, () -> new IsolateBlock<Integer, Integer>(null));
    assertThrows(NullPointerException.class, () -> new SyncCollectorBlock<Integer>(null));
    assertThrows(NullPointerException.class, () -> new AsyncCollectorBlock<Integer>(null));
  }
}

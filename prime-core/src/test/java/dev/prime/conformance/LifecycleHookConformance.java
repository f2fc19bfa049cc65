package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertDoesNotThrow;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreClosedException;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import java.time.Duration;
import java.util.List;
import java.util.Set;
import java.util.concurrent.ConcurrentHashMap;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicBoolean;
import java.util.concurrent.atomic.AtomicReference;
import org.junit.jupiter.api.Test;

/** {@link PrimeCore#whenRunning}: work beside the diagram started and stopped with the core. */
public interface LifecycleHookConformance extends ConformanceBase {

  @Test
  default void aHookStartsWithTheCoreCanPublishThenAndClosesOnceWithIt() throws InterruptedException {
    List<String> calls = new CopyOnWriteArrayList<>();
    PrimeCore core = newCore();
    try (core) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> reader = core.source("fed", events).reader();
      core.whenRunning(
          "feeder",
          () -> {
            calls.add("start");
            events.publish(7); // the core counts as started: a media that refuses early publishes accepts it
          },
          () -> calls.add("close"));
      assertEquals(List.of(), calls, "nothing runs before start()");
      core.start();
      assertEquals(List.of("start"), calls);
      assertEquals(7, takeOrFail(reader));
      List<String> late = new CopyOnWriteArrayList<>();
      core.whenRunning("late", () -> late.add(Thread.currentThread().getName()), () -> late.add("close"));
      assertEquals(List.of(Thread.currentThread().getName()), late, "a hook added to a started core starts at once, here");
      core.close();
      core.close();
      assertEquals(List.of("start", "close"), calls);
      assertEquals(2, late.size());
    }
    assertThrows(CoreClosedException.class, () -> core.whenRunning("after", () -> {}, () -> {}));
  }

  /**
   * A hook's {@code onClose} that closes its core again (the stop routine a program also calls
   * itself) returns at once: the close under way is its own caller ({@link PrimeCore#close()}).
   */
  @Test
  default void aHookThatClosesItsCoreFromItsOnCloseReturnsAtOnce() {
    AtomicReference<Duration> again = new AtomicReference<>();
    PrimeCore core = newCore();
    core.whenRunning(
        "stopper",
        () -> {},
        () -> {
          long began = System.nanoTime();
          core.close();
          again.set(Duration.ofNanos(System.nanoTime() - began));
        });
    core.start();
    core.close();
    assertTrue(
        again.get() != null && again.get().compareTo(Duration.ofSeconds(1)) < 0,
        "the close() inside the hook's onClose returned at once: " + again.get());
  }

  @Test
  default void aHookOfACoreNeverStartedOnlyCloses() {
    List<String> calls = new CopyOnWriteArrayList<>();
    PrimeCore core = newCore();
    core.whenRunning("feeder", () -> calls.add("start"), () -> calls.add("close"));
    core.close();
    assertEquals(List.of("close"), calls);
  }

  @Test
  default void aHookThatThrowsGoesToTheErrorHandlerAndStartCarriesOn() throws InterruptedException {
    List<Object[]> failures = new CopyOnWriteArrayList<>();
    CoreConfig config = handledInto(failures);
    IllegalStateException boom = new IllegalStateException("boom");
    List<String> calls = new CopyOnWriteArrayList<>();
    try (PrimeCore core = newCore(config)) {
      core.whenRunning("broken", () -> { throw boom; }, () -> calls.add("broken closed"));
      core.whenRunning("fine", () -> calls.add("fine started"), () -> {});
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> reader = core.link(core.source(events), core.chain((Integer x) -> x + 1)).reader();
      core.start();
      events.publish(1);
      assertEquals(2, takeOrFail(reader));
      assertEquals(List.of("fine started"), calls);
      assertEquals(1, failures.size());
      assertEquals("broken", failures.get(0)[0]);
      assertEquals("start", failures.get(0)[1]);
      assertSame(boom, failures.get(0)[2]);
    }
    assertEquals(List.of("fine started", "broken closed"), calls);
  }

  /**
   * {@code onClose} runs when the core closes but before its sources close: a reader blocked in
   * {@code take()} on another thread is still waiting while it runs, and wakes with {@code
   * CoreClosedException} afterwards; an exception from {@code onClose} goes to the error handler
   * under the hook's name with {@code "close"} as the input, and the close carries on
   * (architecture, <i>Lifecycle of a core</i>; {@code PrimeCore.whenRunning}).
   */
  @Test
  default void aHookClosesBeforeItsSourcesAndAFailureOfItsCloseGoesToTheErrorHandler()
      throws InterruptedException {
    List<Object[]> failures = new CopyOnWriteArrayList<>();
    CoreConfig config = handledInto(failures);
    IllegalStateException boom = new IllegalStateException("cannot stop");
    CountDownLatch taking = new CountDownLatch(1);
    CountDownLatch woken = new CountDownLatch(1);
    AtomicReference<Throwable> wokenWith = new AtomicReference<>();
    List<String> calls = new CopyOnWriteArrayList<>();
    PrimeCore core = newCore(config);
    Thread taker;
    try (core) {
      Reader<Integer> reader = core.source("fed", new EventBlock<Integer>()).reader();
      core.whenRunning(
          "stopper",
          () -> {},
          () -> {
            calls.add(woken.getCount() == 1 ? "closed with the reader waiting" : "closed after the reader woke");
            throw boom;
          });
      core.whenRunning("next", () -> {}, () -> calls.add("next closed"));
      core.start();
      taker =
          new Thread(
              () -> {
                taking.countDown();
                try {
                  reader.take();
                } catch (Throwable t) {
                  wokenWith.set(t);
                } finally {
                  woken.countDown();
                }
              },
              "kit-taker");
      taker.setDaemon(true);
      taker.start();
      assertTrue(taking.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      long deadline = System.nanoTime() + TimeUnit.MILLISECONDS.toNanos(500);
      while (taker.getState() == Thread.State.RUNNABLE && System.nanoTime() < deadline) {
        Thread.yield(); // until the taker waits in take() (a network media may read a socket)
      }
    }
    assertTrue(woken.await(patience().toMillis(), TimeUnit.MILLISECONDS), "the reader woke at close");
    assertInstanceOf(CoreClosedException.class, wokenWith.get());
    assertEquals(List.of("closed with the reader waiting", "next closed"), calls);
    assertEquals(1, failures.size());
    assertEquals("stopper", failures.get(0)[0]);
    assertEquals("close", failures.get(0)[1]);
    assertSame(boom, failures.get(0)[2]);
  }

  /**
   * A hook that throws while the error handler itself throws: the handler's failure is logged and
   * ignored, as for a service ({@link dev.prime.ErrorHandler}), so {@code start()} and {@code
   * close()} carry on whole. {@code start()} starts the other hooks; {@code close()} closes them,
   * stops the services, wakes the readers with {@code CoreClosedException} and leaves no thread.
   */
  @Test
  default void aHookFailureTheErrorHandlerCannotTakeLeavesStartAndCloseWhole()
      throws InterruptedException {
    List<String> handled = new CopyOnWriteArrayList<>();
    CoreConfig config =
        CoreConfig.builder()
            .errorHandler(
                (service, input, error) -> {
                  handled.add(service + " " + input);
                  throw new IllegalStateException("the error handler is down");
                })
            .build();
    List<String> calls = new CopyOnWriteArrayList<>();
    PrimeCore core = newCore(config);
    Reader<Integer> reader;
    try (core) {
      core.whenRunning(
          "broken",
          () -> {
            throw new IllegalStateException("cannot start");
          },
          () -> {
            throw new IllegalStateException("cannot stop");
          });
      core.whenRunning("fine", () -> calls.add("fine started"), () -> calls.add("fine closed"));
      EventBlock<Integer> events = new EventBlock<>();
      reader = core.link(core.source(events), core.chain((Integer x) -> x + 1)).reader();
      assertDoesNotThrow(core::start, "start() with a failing hook and a failing error handler");
      assertEquals(List.of("fine started"), calls, "the hook after the failing one started");
      events.publish(1);
      assertEquals(2, takeOrFail(reader));
      assertDoesNotThrow(core::close, "close() with a failing hook and a failing error handler");
    }
    assertEquals(List.of("fine started", "fine closed"), calls, "the hook after the failing one closed");
    assertEquals(List.of("broken start", "broken close"), handled);
    assertThrows(CoreClosedException.class, reader::poll, "the core's sources closed");
    awaitNoThreadsLeft(core);
  }

  /**
   * A hook that throws a checked exception without declaring it (a Kotlin hook's {@code
   * IOException}) goes to the error handler like any other failure, and {@code start()} and
   * {@code close()} carry on whole: the other hooks run, the services stop, no thread is left.
   */
  @Test
  default void aHookThrowingACheckedExceptionGoesToTheErrorHandlerAndStartAndCloseCarryOn()
      throws InterruptedException {
    List<Object[]> failures = new CopyOnWriteArrayList<>();
    CoreConfig config = handledInto(failures);
    java.io.IOException cannotStart = new java.io.IOException("cannot open the port");
    java.io.IOException cannotStop = new java.io.IOException("cannot close the port");
    List<String> calls = new CopyOnWriteArrayList<>();
    PrimeCore core = newCore(config);
    Reader<Integer> reader;
    try (core) {
      core.whenRunning(
          "port",
          () -> {
            throw LifecycleHookConformance.<RuntimeException>sneaky(cannotStart);
          },
          () -> {
            throw LifecycleHookConformance.<RuntimeException>sneaky(cannotStop);
          });
      core.whenRunning("fine", () -> calls.add("fine started"), () -> calls.add("fine closed"));
      EventBlock<Integer> events = new EventBlock<>();
      reader = core.link(core.source(events), core.chain((Integer x) -> x + 1)).reader();
      assertDoesNotThrow(core::start, "start() with a hook that throws a checked exception");
      events.publish(1);
      assertEquals(2, takeOrFail(reader));
      assertDoesNotThrow(core::close, "close() with a hook that throws a checked exception");
    }
    assertEquals(List.of("fine started", "fine closed"), calls);
    assertEquals(2, failures.size());
    assertEquals("port", failures.get(0)[0]);
    assertEquals("start", failures.get(0)[1]);
    assertSame(cannotStart, failures.get(0)[2]);
    assertEquals("close", failures.get(1)[1]);
    assertSame(cannotStop, failures.get(1)[2]);
    assertThrows(CoreClosedException.class, reader::poll, "the core's sources closed");
    awaitNoThreadsLeft(core);
  }

  /** A config whose error handler adds each failure to {@code failures} as (service, input, error). */
  private static CoreConfig handledInto(List<Object[]> failures) {
    return CoreConfig.builder()
        .errorHandler((service, input, error) -> failures.add(new Object[] {service, input, error}))
        .build();
  }

  /** Throws any throwable, checked or not, without declaring it. */
  @SuppressWarnings("unchecked")
  private static <E extends Throwable> RuntimeException sneaky(Throwable t) throws E {
    throw (E) t;
  }

  /**
   * {@link PrimeCore#whenRunning}: "{@code onStart} runs when the core starts, after its
   * services". A hook's {@code onStart} publishes to a source linked to a chain and waits (at most
   * the kit's patience) for the chain to process the value: that can happen only if the service
   * already runs. (A real hook must return quickly; this one returns as soon as the service has
   * the value.)
   */
  @Test
  default void aHooksOnStartRunsAfterTheCoresServicesStarted() throws InterruptedException {
    CountDownLatch processed = new CountDownLatch(1);
    AtomicReference<Boolean> servedDuringOnStart = new AtomicReference<>();
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      core.link(
          core.source("fed", events),
          core.chain(
              "served",
              (Integer x) -> {
                processed.countDown();
                return x;
              }));
      core.whenRunning(
          "feeder",
          () -> {
            events.publish(7);
            try {
              servedDuringOnStart.set(
                  processed.await(patience().toMillis(), TimeUnit.MILLISECONDS));
            } catch (InterruptedException e) {
              Thread.currentThread().interrupt();
              servedDuringOnStart.set(false);
            }
          },
          () -> {});
      core.start();
      assertEquals(
          Boolean.TRUE,
          servedDuringOnStart.get(),
          "the service processed the value onStart published while onStart ran");
    }
  }
  /**
   * A close that comes while a hook's {@code onStart} runs (from {@code start()}) closes the hook
   * after its start returned, and {@code close()} returns only then: what the start left (a
   * metrics binder's meters, here a set standing for the registry) is gone when {@code close()}
   * returns ({@link PrimeCore#whenRunning}).
   */
  @Test
  default void aCloseWhileAHookStartsClosesItAfterItsStart() throws InterruptedException {
    PrimeCore core = newCore();
    HookRace race = new HookRace();
    core.whenRunning("binder", race::onStart, race::onClose);
    Thread starter = HookRace.thread(core::start, "kit-starter");
    race.closeWhileStarting(core, this);
    starter.join(patience().toMillis());
    race.assertClosedAfterItsStart();
    awaitNoThreadsLeft(core);
  }

  /**
   * The same for a hook added to a started core, whose {@code onStart} runs on the adding thread:
   * a close that comes meanwhile closes it after its start returned.
   */
  @Test
  default void aCloseWhileAHookAddedLateStartsClosesItAfterItsStart() throws InterruptedException {
    PrimeCore core = newCore();
    core.start();
    HookRace race = new HookRace();
    Thread adder =
        HookRace.thread(() -> core.whenRunning("binder", race::onStart, race::onClose), "kit-adder");
    race.closeWhileStarting(core, this);
    adder.join(patience().toMillis());
    race.assertClosedAfterItsStart();
    awaitNoThreadsLeft(core);
  }

  /**
   * A hook's {@code onStart} that closes its core (a start that finds it cannot go on) returns,
   * and its {@code onClose} runs after it, on the same thread, before {@code start()} returns;
   * the hooks after it neither start nor stay open.
   */
  @Test
  default void aHookThatClosesItsCoreFromItsOnStartIsClosedAfterIt() {
    List<String> calls = new CopyOnWriteArrayList<>();
    PrimeCore core = newCore();
    core.whenRunning(
        "quitter",
        () -> {
          calls.add("start begun");
          core.close();
          calls.add("start done");
        },
        () -> calls.add("close"));
    core.whenRunning("next", () -> calls.add("next started"), () -> calls.add("next closed"));
    core.start();
    assertTrue(core.isClosed());
    assertEquals(List.of("start begun", "next closed", "start done", "close"), calls);
  }

  /**
   * A {@code close()} from one of the core's own threads (a generic service) while a hook's
   * {@code onStart} runs on the starting thread does not wait for that start, which may itself
   * wait for the service: it returns, and the hook's {@code onClose} runs on the starting thread as
   * its {@code onStart} returns ({@link PrimeCore#whenRunning}). The shutdown timeout is far above
   * the kit's patience, so a close that waited for the start would outlast the start's own wait.
   */
  @Test
  default void aCloseFromAServiceWhileAHookStartsLeavesTheHooksCloseToItsStart()
      throws InterruptedException {
    List<String> calls = new CopyOnWriteArrayList<>();
    CountDownLatch starting = new CountDownLatch(1);
    CountDownLatch closeReturned = new CountDownLatch(1);
    AtomicBoolean closing = new AtomicBoolean();
    Duration patience = patience();
    PrimeCore core =
        newCore(CoreConfig.builder().shutdownTimeout(patience.multipliedBy(3)).build());
    try {
      core.service(
          "stopper",
          () -> {
            if (closing.getAndSet(true)) {
              return; // closed once; the service stops with its core
            }
            if (starting.await(patience.toMillis(), TimeUnit.MILLISECONDS)) {
              core.close();
              calls.add("close() returned");
            }
            closeReturned.countDown();
          });
      core.whenRunning(
          "waiter",
          () -> {
            calls.add("start begun");
            starting.countDown();
            try {
              if (!closeReturned.await(patience.toMillis(), TimeUnit.MILLISECONDS)) {
                calls.add("close() waited for the start");
              }
            } catch (InterruptedException e) {
              Thread.currentThread().interrupt();
            }
            calls.add("start done");
          },
          () -> calls.add("close"));
      core.start();
      assertEquals(
          List.of("start begun", "close() returned", "start done", "close"),
          calls,
          "close() from the service returned while the hook started, and the hook closed after");
      assertTrue(core.isClosed());
    } finally {
      core.close();
    }
  }

  /**
   * A hook whose {@code onStart} waits for the test while a close comes, standing for a metrics
   * binder: its start registers a meter, its close removes the meters. The test's loops are bound
   * by the kit's patience.
   */
  final class HookRace {
    final Set<String> registry = ConcurrentHashMap.newKeySet();
    final List<String> calls = new CopyOnWriteArrayList<>();
    final CountDownLatch starting = new CountDownLatch(1);
    final CountDownLatch release = new CountDownLatch(1);
    final CountDownLatch closedEarly = new CountDownLatch(1);
    final CountDownLatch closeReturned = new CountDownLatch(1);
    Duration patience = Duration.ofSeconds(20);

    void onStart() {
      calls.add("start begun");
      starting.countDown();
      try {
        release.await(patience.toMillis(), TimeUnit.MILLISECONDS);
      } catch (InterruptedException e) {
        Thread.currentThread().interrupt();
      }
      registry.add("meter");
      calls.add("start done");
    }

    void onClose() {
      calls.add("close");
      closedEarly.countDown();
      registry.clear();
    }

    /**
     * Once the hook's start runs, closes the core on another thread, lets the start finish once
     * that close waits (or closed the hook already: the defect) and waits for it to return.
     */
    void closeWhileStarting(PrimeCore core, ConformanceBase kit) throws InterruptedException {
      patience = kit.patience();
      assertTrue(starting.await(patience.toMillis(), TimeUnit.MILLISECONDS), "the hook started");
      Thread closer =
          thread(
              () -> {
                core.close();
                calls.add("close() returned with " + registry);
                closeReturned.countDown();
              },
              "kit-closer");
      long deadline = System.nanoTime() + patience.toNanos();
      for (int i = 0; i < 100_000 && System.nanoTime() < deadline; i++) {
        Thread.State state = closer.getState();
        if (state == Thread.State.WAITING
            || state == Thread.State.TIMED_WAITING
            || state == Thread.State.TERMINATED
            || closedEarly.await(1, TimeUnit.MILLISECONDS)) {
          break; // the close waits for the start, or went past it
        }
      }
      release.countDown();
      assertTrue(closeReturned.await(patience.toMillis(), TimeUnit.MILLISECONDS), "close() returned");
      closer.join(patience.toMillis());
    }

    void assertClosedAfterItsStart() {
      assertEquals(
          List.of("start begun", "start done", "close", "close() returned with []"),
          calls,
          "the hook's close runs after its start, and close() returns after both");
      assertEquals(Set.of(), registry, "nothing the hook's start made is left after close()");
    }

    static Thread thread(Runnable action, String name) {
      Thread thread = new Thread(action, name);
      thread.setDaemon(true);
      thread.start();
      return thread;
    }
  }
}

package dev.prime.conformance;

import static dev.prime.conformance.ConformanceBase.assertNoThreadsLeft;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertNotSame;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.CoreClosedException;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.GenericService;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.topology.Topology;
import dev.prime.topology.TopologyNode;
import java.time.Duration;
import java.util.List;
import java.util.Set;
import java.util.UUID;
import java.util.concurrent.ConcurrentHashMap;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicBoolean;
import java.util.concurrent.atomic.AtomicInteger;
import org.junit.jupiter.api.Assumptions;
import org.junit.jupiter.api.Test;

/**
 * Generic services ({@link PrimeCore#service(String, GenericService)}): started by the core,
 * initialized once, worked over and over on one thread, failures to the error handler under the
 * service's name, stopped promptly by close even while a work step waits, shut down once, and on
 * a media of several processes run only where hosted.
 */
public interface GenericServiceConformance extends ConformanceBase {

  /**
   * A core of the media under test that shares one topology with every other core made from
   * {@code config} (the same core name) and runs only {@code services} of it; {@code null} for a
   * media whose cores run every service they declare (Liberty, Radiant). Optimus builds a core on
   * the kit's Redis with {@code hosts(services)}.
   */
  default PrimeCore newCoreHosting(CoreConfig config, Set<String> services) {
    return null;
  }

  /** What a generic service under test did, and when. */
  class Recording implements GenericService {
    final AtomicInteger initializations = new AtomicInteger();
    final AtomicInteger works = new AtomicInteger();
    final AtomicInteger shutdowns = new AtomicInteger();
    final Set<Thread> threads = ConcurrentHashMap.newKeySet();
    final CountDownLatch worked;
    volatile CountDownLatch nextWorks = new CountDownLatch(0);
    volatile boolean interruptedInShutdown;

    Recording(int works) {
      this.worked = new CountDownLatch(works);
    }

    @Override
    public void initialize() throws Exception {
      threads.add(Thread.currentThread());
      initializations.incrementAndGet();
    }

    @Override
    public void work() throws Exception {
      threads.add(Thread.currentThread());
      works.incrementAndGet();
      worked.countDown();
      nextWorks.countDown();
      step(works.get());
    }

    /** What work number {@code n} does after it is counted; by default waits a little. */
    void step(int n) throws Exception {
      Thread.sleep(1);
    }

    @Override
    public void shutdown() {
      threads.add(Thread.currentThread());
      interruptedInShutdown = Thread.currentThread().isInterrupted();
      shutdowns.incrementAndGet();
    }
  }

  /** One call of the error handler. */
  record Failure(String service, Object input, Throwable error) {}

  private CoreConfig recordingFailures(List<Failure> failures) {
    return CoreConfig.builder()
        .errorHandler((service, input, error) -> failures.add(new Failure(service, input, error)))
        .build();
  }

  private boolean await(CountDownLatch latch) throws InterruptedException {
    return latch.await(patience().toMillis(), TimeUnit.MILLISECONDS);
  }

  @Test
  default void aGenericServiceStartsOnStartWorksOverAndOverAndShutsDownOnceOnClose()
      throws InterruptedException {
    AtomicBoolean startedBeforeInitialize = new AtomicBoolean();
    PrimeCore core = newCore();
    Recording driver =
        new Recording(5) {
          @Override
          public void initialize() throws Exception {
            startedBeforeInitialize.set(core.isStarted());
            super.initialize();
          }
        };
    try (core) {
      core.service("driver", driver);
      assertEquals(0, driver.initializations.get(), "declaring runs nothing");
      core.start();
      assertTrue(await(driver.worked), "work ran 5 times; it ran " + driver.works.get());
      assertTrue(startedBeforeInitialize.get(), "initialize runs only once the core is started");
      assertEquals(1, driver.initializations.get(), "initialize once");
      assertEquals(0, driver.shutdowns.get(), "no shutdown while the core runs");
    }
    assertEquals(1, driver.initializations.get(), "initialize exactly once");
    assertEquals(1, driver.shutdowns.get(), "shutdown exactly once, before close returned");
    assertEquals(1, driver.threads.size(), "one thread for every step: " + driver.threads);
    assertNotSame(Thread.currentThread(), driver.threads.iterator().next());
    assertFalse(driver.interruptedInShutdown, "shutdown runs with the interrupt flag cleared");
    assertNoThreadsLeft(core);
  }

  @Test
  default void aGenericServiceDeclaredAfterStartStartsAtOnceAndCanFeedASource()
      throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> readings = new EventBlock<>();
      Reader<Integer> reader = core.source("readings", readings).reader();
      core.start();
      AtomicInteger next = new AtomicInteger();
      core.service(
          "poller",
          () -> {
            int n = next.incrementAndGet();
            if (n <= 3) {
              readings.publish(n);
            } else {
              Thread.sleep(5);
            }
          });
      assertEquals(List.of(1, 2, 3), takeOrFail(reader, 3));
    }
  }

  @Test
  default void aFailingWorkGoesToTheErrorHandlerUnderTheServiceNameAndTheServiceGoesOn()
      throws InterruptedException {
    List<Failure> failures = new CopyOnWriteArrayList<>();
    ErrorConformance.Boom boom = new ErrorConformance.Boom("the device did not answer");
    AssertionError error = new AssertionError("an Error does not end it either");
    Recording driver =
        new Recording(6) {
          @Override
          void step(int n) throws Exception {
            if (n == 2) {
              throw boom;
            }
            if (n == 3) {
              throw error;
            }
          }
        };
    PrimeCore core = newCore(recordingFailures(failures));
    try (core) {
      core.service("flaky-driver", driver);
      core.start();
      assertTrue(await(driver.worked), "work goes on after failures; it ran " + driver.works.get());
    }
    assertEquals(2, failures.size(), "each failure reported once: " + failures);
    for (Failure failure : failures) {
      assertEquals("flaky-driver", failure.service());
      assertEquals(GenericService.Step.WORK, failure.input());
    }
    assertSame(boom, failures.get(0).error(), "the work's own throwable");
    assertSame(error, failures.get(1).error());
    assertEquals(1, driver.initializations.get());
    assertEquals(1, driver.shutdowns.get());
  }

  /**
   * {@link GenericService}, "Failures": a {@link VirtualMachineError} a {@code work} throws is not
   * a failure of the step but "ends the service": it is not reported to the error handler, no
   * {@code work} runs after it, and, {@code initialize} having succeeded, {@code shutdown} runs
   * once at once (not only at {@code close()}). The core's other services go on, and {@code
   * close()} still leaves no thread.
   */
  @Test
  default void aVirtualMachineErrorInWorkEndsTheServiceWithoutAReport() throws InterruptedException {
    List<Failure> failures = new CopyOnWriteArrayList<>();
    OutOfMemoryError oom = new OutOfMemoryError("thrown by the work of 'doomed' on purpose");
    AtomicInteger works = new AtomicInteger();
    AtomicInteger shutdowns = new AtomicInteger();
    CountDownLatch shutDown = new CountDownLatch(1);
    CountDownLatch neverOpened = new CountDownLatch(1);
    GenericService doomed =
        new GenericService() {
          @Override
          public void work() throws Exception {
            if (works.incrementAndGet() == 1) {
              throw oom;
            }
            neverOpened.await(); // a second work would wait here until close interrupts it
          }

          @Override
          public void shutdown() {
            shutdowns.incrementAndGet();
            shutDown.countDown();
          }
        };
    Recording other = new Recording(3);
    PrimeCore core = newCore(recordingFailures(failures));
    try (core) {
      core.service("doomed", doomed);
      core.service("other", other);
      core.start();
      assertTrue(
          await(shutDown),
          "the service ended, and shut down, right after the error; works: " + works.get());
      assertEquals(1, works.get(), "no work runs after a VirtualMachineError");
      assertTrue(await(other.worked), "the other service goes on: " + other.works.get());
    }
    assertEquals(List.of(), failures, "a VirtualMachineError does not go to the error handler");
    assertEquals(1, shutdowns.get(), "shutdown ran once");
    assertNoThreadsLeft(core);
  }

  @Test
  default void aChainThatFailsInAWorkStepIsReportedLikeInAnyService() throws InterruptedException {
    List<Failure> failures = new CopyOnWriteArrayList<>();
    ErrorConformance.Boom boom = new ErrorConformance.Boom("cannot parse");
    PrimeCore core = newCore(recordingFailures(failures));
    try (core) {
      Block<String, Integer> parse =
          core.chain(
                  "parse",
                  (String text) -> {
                    if (text.isEmpty()) {
                      throw boom;
                    }
                    return text.length();
                  })
              .toBlock();
      core.start();
      Recording poller =
          new Recording(3) {
            @Override
            void step(int n) throws Exception {
              parse.process(n == 1 ? "" : "ok");
            }
          };
      core.service("poller", poller);
      assertTrue(await(poller.worked), "work goes on; it ran " + poller.works.get());
    }
    assertEquals(
        List.of(new Failure("parse", GenericService.Step.WORK, boom)),
        failures,
        "the chain that failed, with its block's own throwable");
  }

  @Test
  default void failuresInARowBackOffAndASuccessResetsTheBackOff() throws InterruptedException {
    List<Integer> backoffs = new CopyOnWriteArrayList<>();
    AtomicInteger works = new AtomicInteger();
    CountDownLatch done = new CountDownLatch(1);
    GenericService driver =
        new GenericService() {
          @Override
          public void work() throws Exception {
            int n = works.incrementAndGet();
            if (n == 1 || n == 2 || n == 4) {
              throw new IllegalStateException("unplugged " + n);
            }
            if (n >= 5) {
              done.countDown();
              Thread.sleep(5);
            }
          }

          @Override
          public Duration backoff(int failures) {
            backoffs.add(failures);
            return Duration.ofMillis(1);
          }
        };
    try (PrimeCore core = newCore(recordingFailures(new CopyOnWriteArrayList<>()))) {
      core.service("backing-off", driver);
      core.start();
      assertTrue(await(done), "work reached its 5th call; calls: " + works.get());
    }
    assertEquals(List.of(1, 2, 1), backoffs, "failures in a row count up; a success resets them");
  }

  /**
   * A {@code backoff} that throws (an {@link AssertionError}, a checked exception of Kotlin code)
   * does not end the service: only a {@link VirtualMachineError} does (architecture, <i>Generic
   * services</i>). The service waits a second instead and goes on with its next step.
   */
  @Test
  default void aBackOffThatThrowsAnErrorDoesNotEndTheService() throws InterruptedException {
    AtomicInteger works = new AtomicInteger();
    CountDownLatch workedAgain = new CountDownLatch(1);
    GenericService driver =
        new GenericService() {
          @Override
          public void work() throws Exception {
            if (works.incrementAndGet() == 1) {
              throw new IllegalStateException("unplugged");
            }
            workedAgain.countDown();
            Thread.sleep(5);
          }

          @Override
          public Duration backoff(int failures) {
            throw new AssertionError("a back-off bug");
          }
        };
    try (PrimeCore core = newCore(recordingFailures(new CopyOnWriteArrayList<>()))) {
      core.service("backing-off", driver);
      core.start();
      assertTrue(await(workedAgain), "work ran again after the failing back-off; calls: " + works.get());
    }
  }

  @Test
  default void theDefaultBackOffKeepsAFailingWorkFromSpinning() throws InterruptedException {
    AtomicInteger works = new AtomicInteger();
    CountDownLatch sixFailures = new CountDownLatch(6);
    List<Failure> failures = new CopyOnWriteArrayList<>();
    CoreConfig config =
        CoreConfig.builder()
            .errorHandler(
                (service, input, error) -> {
                  failures.add(new Failure(service, input, error));
                  sixFailures.countDown();
                })
            .build();
    long started;
    long took;
    try (PrimeCore core = newCore(config)) {
      core.service(
          "always-failing",
          () -> {
            works.incrementAndGet();
            throw new IllegalStateException("no device");
          });
      started = System.nanoTime();
      core.start();
      assertTrue(await(sixFailures), "six failures reported; " + failures.size());
      took = System.nanoTime() - started;
    }
    // waits after failures 1..5 before works 2..6: 10 + 20 + 40 + 80 + 160 ms
    assertTrue(
        took >= TimeUnit.MILLISECONDS.toNanos(310),
        "six failing works took at least the back-off between them (310 ms), not "
            + TimeUnit.NANOSECONDS.toMillis(took) + " ms");
    assertTrue(works.get() <= 8, "the work did not spin: " + works.get() + " calls");
  }

  @Test
  default void aFailingInitializeIsReportedAndTriedAgainBeforeAnyWork()
      throws InterruptedException {
    List<Failure> failures = new CopyOnWriteArrayList<>();
    ErrorConformance.Boom notYet = new ErrorConformance.Boom("port not there yet");
    ErrorConformance.Boom cannotClose = new ErrorConformance.Boom("port stuck");
    Recording driver =
        new Recording(3) {
          @Override
          public void initialize() throws Exception {
            super.initialize();
            if (initializations.get() <= 2) {
              assertEquals(0, works.get(), "no work before initialize succeeded");
              throw notYet;
            }
          }

          @Override
          public void shutdown() {
            super.shutdown();
            throw cannotClose;
          }
        };
    PrimeCore core = newCore(recordingFailures(failures));
    try (core) {
      core.service("late-driver", driver);
      core.start();
      assertTrue(await(driver.worked), "work ran once initialize succeeded");
    }
    assertEquals(3, driver.initializations.get(), "tried again until it succeeded");
    assertEquals(1, driver.shutdowns.get(), "shut down once");
    assertEquals(
        List.of(
            new Failure("late-driver", GenericService.Step.INITIALIZE, notYet),
            new Failure("late-driver", GenericService.Step.INITIALIZE, notYet),
            new Failure("late-driver", GenericService.Step.SHUTDOWN, cannotClose)),
        failures);
  }

  @Test
  default void closeInterruptsAWorkStepThatWaitsAndReturnsPromptlyWithoutWarnings()
      throws InterruptedException {
    List<Failure> failures = new CopyOnWriteArrayList<>();
    CountDownLatch waiting = new CountDownLatch(1);
    AtomicBoolean interrupted = new AtomicBoolean();
    Recording driver =
        new Recording(1) {
          @Override
          void step(int n) throws Exception {
            waiting.countDown();
            try {
              new CountDownLatch(1).await(); // a read that never returns by itself
            } catch (InterruptedException e) {
              interrupted.set(true);
              throw e;
            }
          }
        };
    String name = "blocked-" + UUID.randomUUID().toString().substring(0, 8);
    Duration shutdownTimeout = Duration.ofSeconds(30);
    PrimeCore core =
        newCore(recordingFailures(failures).toBuilder().shutdownTimeout(shutdownTimeout).build());
    long took;
    List<String> lines;
    try (CapturedStderr err = new CapturedStderr()) {
      core.service(name, driver);
      core.start();
      assertTrue(await(waiting), "the work step is waiting");
      long started = System.nanoTime();
      core.close();
      took = System.nanoTime() - started;
      lines = err.lines();
    }
    assertTrue(interrupted.get(), "close interrupted the waiting work step");
    assertTrue(
        took < shutdownTimeout.toNanos() / 3,
        "close returned in " + TimeUnit.NANOSECONDS.toMillis(took) + " ms, without waiting for"
            + " the shutdown timeout of " + shutdownTimeout);
    assertEquals(1, driver.works.get(), "no work after close");
    assertEquals(1, driver.shutdowns.get(), "shut down once, before close returned");
    assertEquals(List.of(), failures, "the interrupt that stops a service is not a failure");
    assertNoThreadsLeft(core);
    List<String> warnings =
        lines.stream()
            .filter(l -> l.contains("WARN") || l.contains("ERROR"))
            .filter(l -> l.contains(core.name()) || l.contains(name))
            .toList();
    assertEquals(List.of(), warnings, "no abandoned or still-running warnings");
  }

  /**
   * {@link GenericService#backoff(int)}: "The wait ends at once when the service stops". Two
   * services wait out a back-off of an hour when the core closes, one after a failed {@code
   * initialize}, one after a failed {@code work}: close returns promptly (far under its shutdown
   * timeout), no step runs again, the one that initialized is shut down once and the other is
   * not.
   */
  @Test
  default void closeEndsABackOffAtOnce() throws InterruptedException {
    List<Failure> failures = new CopyOnWriteArrayList<>();
    CountDownLatch bothFailed = new CountDownLatch(2);
    AtomicInteger initializeTries = new AtomicInteger();
    AtomicInteger initializeShutdowns = new AtomicInteger();
    GenericService neverInitialized =
        new GenericService() {
          @Override
          public void initialize() {
            initializeTries.incrementAndGet();
            throw new IllegalStateException("no device yet");
          }

          @Override
          public void work() {
            throw new AssertionError("work before initialize succeeded");
          }

          @Override
          public void shutdown() {
            initializeShutdowns.incrementAndGet();
          }

          @Override
          public Duration backoff(int failures) {
            return Duration.ofHours(1);
          }
        };
    Recording failingWork =
        new Recording(1) {
          @Override
          void step(int n) {
            throw new IllegalStateException("unplugged");
          }

          @Override
          public Duration backoff(int failures) {
            return Duration.ofHours(1);
          }
        };
    Duration shutdownTimeout = Duration.ofSeconds(30);
    CoreConfig config =
        CoreConfig.builder()
            .errorHandler(
                (service, input, error) -> {
                  failures.add(new Failure(service, input, error));
                  bothFailed.countDown();
                })
            .shutdownTimeout(shutdownTimeout)
            .build();
    PrimeCore core = newCore(config);
    long took;
    try {
      core.service("backing-off-initialize", neverInitialized);
      core.service("backing-off-work", failingWork);
      core.start();
      assertTrue(await(bothFailed), "both services failed once; failures: " + failures);
    } finally {
      long started = System.nanoTime();
      core.close();
      took = System.nanoTime() - started;
    }
    assertTrue(
        took < shutdownTimeout.toNanos() / 3,
        "close ended the back-offs at once: it returned in "
            + TimeUnit.NANOSECONDS.toMillis(took)
            + " ms, not within a third of the shutdown timeout of "
            + shutdownTimeout);
    assertEquals(1, initializeTries.get(), "initialize was not tried again after close");
    assertEquals(0, initializeShutdowns.get(), "a service never initialized is not shut down");
    assertEquals(1, failingWork.works.get(), "no work after close");
    assertEquals(1, failingWork.shutdowns.get(), "the initialized service was shut down once");
    assertEquals(2, failures.size(), "only the two failures were reported: " + failures);
    assertNoThreadsLeft(core);
  }

  /**
   * {@link dev.prime.GenericServiceLoop}: "an interrupt alone (a stray one from user code) is a
   * failure of the step it ended, reported and followed by the next step". A work step interrupts
   * its own thread and returns; the next one's wait ends with an {@link InterruptedException},
   * which is reported under the service's name as a failed {@code WORK}, and the work goes on.
   */
  @Test
  default void aStrayInterruptIsAFailureOfTheStepItEndedAndTheServiceGoesOn()
      throws InterruptedException {
    List<Failure> failures = new CopyOnWriteArrayList<>();
    CountDownLatch wentOn = new CountDownLatch(1);
    Recording driver =
        new Recording(1) {
          @Override
          void step(int n) throws Exception {
            if (n == 1) {
              Thread.currentThread().interrupt(); // a stray interrupt from user code
            } else if (n == 2) {
              Thread.sleep(10_000); // ends at once: the flag is set
            } else {
              wentOn.countDown();
              Thread.sleep(1);
            }
          }

          @Override
          public Duration backoff(int failures) {
            return Duration.ofMillis(1);
          }
        };
    String name = "stray-interrupt";
    try (PrimeCore core = newCore(recordingFailures(failures))) {
      core.service(name, driver);
      core.start();
      assertTrue(
          await(wentOn),
          "the service went on after a stray interrupt; works: "
              + driver.works.get()
              + ", failures: "
              + failures);
    }
    assertEquals(1, failures.size(), "one failure: " + failures);
    Failure failure = failures.get(0);
    assertEquals(name, failure.service());
    assertEquals(GenericService.Step.WORK, failure.input());
    assertInstanceOf(InterruptedException.class, failure.error());
    assertEquals(1, driver.shutdowns.get(), "shut down once, at close");
  }

  /**
   * architecture.md (generic services): "A {@code work()} stuck in uninterruptible I/O cannot be
   * stopped and is reported as abandoned when the timeout passes", and {@link GenericService}:
   * {@code shutdown} runs after the last {@code work}. A work step deaf to interrupts does not
   * hold {@code close()} up: it returns within a few shutdown timeouts (under 5 s here, with a
   * timeout of 200 ms), and a WARN line naming the core says a service is still running; once the
   * stuck step returns, no work follows, {@code shutdown} runs once and the thread ends.
   */
  @Test
  default void aWorkStuckPastTheShutdownTimeoutIsReportedAndShutDownWhenItReturns()
      throws InterruptedException {
    Duration shutdownTimeout = Duration.ofMillis(200);
    long holdNanos = patience().toNanos();
    CountDownLatch inside = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    CountDownLatch shutDown = new CountDownLatch(1);
    AtomicInteger works = new AtomicInteger();
    AtomicInteger shutdowns = new AtomicInteger();
    GenericService deaf =
        new GenericService() {
          @Override
          public void work() {
            works.incrementAndGet();
            inside.countDown();
            long deadline = System.nanoTime() + holdNanos;
            while (System.nanoTime() < deadline) {
              try {
                if (release.await(deadline - System.nanoTime(), TimeUnit.NANOSECONDS)) {
                  return;
                }
              } catch (InterruptedException deafToIt) {
                // like uninterruptible I/O: waits on until released (bounded by the patience)
              }
            }
          }

          @Override
          public void shutdown() {
            shutdowns.incrementAndGet();
            shutDown.countDown();
          }
        };
    PrimeCore core = newCore(CoreConfig.builder().shutdownTimeout(shutdownTimeout).build());
    CapturedStderr err = new CapturedStderr();
    long took;
    List<String> lines;
    try {
      core.service("deaf-driver", deaf);
      core.start();
      assertTrue(await(inside), "the work step runs");
      long began = System.nanoTime();
      core.close();
      took = System.nanoTime() - began;
      lines = err.lines();
    } finally {
      release.countDown();
      err.close();
    }
    assertTrue(
        took < shutdownTimeout.multipliedBy(5).plusSeconds(4).toNanos(),
        "close() waited " + TimeUnit.NANOSECONDS.toMillis(took) + " ms with a shutdown timeout of "
            + shutdownTimeout);
    String named = "core '" + core.name() + "'";
    assertTrue(
        lines.stream().anyMatch(l -> l.contains(named) && l.contains("still running")),
        "close() said that a service of " + named + " is still running: " + lines);
    assertTrue(await(shutDown), "shutdown ran once the stuck work returned");
    awaitNoThreadsLeft(core);
    assertEquals(1, works.get(), "no work after the stuck one");
    assertEquals(1, shutdowns.get(), "shut down once");
  }

  /**
   * A generic service that closes its own core (it saw a stop command), next to another service,
   * with a shutdown timeout far above the kit's patience: a close that waited for its own thread
   * would take that long, and one cut short would complain about threads still running.
   */
  @Test
  default void aGenericServiceMayCloseItsOwnCore() throws InterruptedException {
    CountDownLatch closeReturned = new CountDownLatch(1);
    CountDownLatch shutDown = new CountDownLatch(1);
    AtomicBoolean interruptedAfterClose = new AtomicBoolean();
    PrimeCore core =
        newCore(CoreConfig.builder().shutdownTimeout(patience().multipliedBy(3)).build());
    Recording stopper =
        new Recording(1) {
          @Override
          void step(int n) {
            if (n == 3) {
              core.close();
              interruptedAfterClose.set(Thread.currentThread().isInterrupted());
              closeReturned.countDown();
            }
          }

          @Override
          public void shutdown() {
            super.shutdown();
            shutDown.countDown();
          }
        };
    List<String> lines;
    try (CapturedStderr err = new CapturedStderr()) {
      core.service("stopper", stopper);
      core.source(new EventBlock<Integer>()).listen(x -> {}); // another service, which it stops
      core.start();
      assertTrue(await(closeReturned), "close() from the service returned within " + patience());
      assertTrue(await(shutDown), "the service shut down after closing its core");
      lines = err.lines();
    } finally {
      core.close();
    }
    assertTrue(core.isClosed());
    assertEquals(3, stopper.works.get(), "no work after the close");
    assertEquals(1, stopper.initializations.get());
    assertEquals(1, stopper.shutdowns.get());
    assertFalse(interruptedAfterClose.get(), "closing its own core does not interrupt the caller");
    for (String complaint : List.of("abandoned", "still running")) {
      List<String> complaints = lines.stream().filter(l -> l.contains(complaint)).toList();
      assertEquals(List.of(), complaints, "the core complained while closing itself");
    }
  }

  @Test
  default void aServiceNeverStartedIsNeitherInitializedNorShutDown() {
    Recording driver = new Recording(1);
    PrimeCore core = newCore();
    core.service("never-started", driver);
    core.close();
    assertEquals(0, driver.initializations.get());
    assertEquals(0, driver.works.get());
    assertEquals(0, driver.shutdowns.get());
    assertNoThreadsLeft(core);
  }

  @Test
  default void aGenericServiceIsANamedServiceOfTheTopology() {
    PrimeCore core = newCore();
    try {
      core.chain("odometry", (Integer x) -> x);
      core.service("lidar", () -> Thread.sleep(5));
      Topology topology = core.topology();
      assertEquals(
          List.of(
              new TopologyNode.BlockChain("odometry"), new TopologyNode.GenericServiceNode("lidar")),
          topology.nodes());
      assertTrue(topology.services().contains("lidar"), "a service: " + topology.services());
      assertTrue(core.serviceNames().contains("lidar"), "hosted here: " + core.serviceNames());
      assertTrue(topology.toMermaid().contains("n2[[\"lidar\"]]"), topology.toMermaid());
      assertTrue(
          topology.toDot().contains("n2 [label=\"lidar\", shape=component];"), topology.toDot());

      IllegalArgumentException taken =
          assertThrows(
              IllegalArgumentException.class, () -> core.service("odometry", () -> {}));
      assertTrue(taken.getMessage().contains("'odometry'"), taken.getMessage());
      assertThrows(IllegalArgumentException.class, () -> core.chain("lidar", (Integer x) -> x));
      assertThrows(IllegalArgumentException.class, () -> core.service("has space", () -> {}));
      assertThrows(NullPointerException.class, () -> core.service(null, () -> {}));
      assertThrows(NullPointerException.class, () -> core.service("no-service", null));
      assertEquals(topology, core.topology(), "a refused declaration records nothing");
      core.close();
      assertThrows(CoreClosedException.class, () -> core.service("too-late", () -> {}));
    } finally {
      core.close();
    }
  }

  @Test
  default void aGenericServiceRunsOnlyInTheProcessThatHostsIt() throws InterruptedException {
    String coreName = "generic-hosting-" + UUID.randomUUID().toString().substring(0, 8);
    CoreConfig config = CoreConfig.builder().name(coreName).build();
    PrimeCore elsewhere = newCoreHosting(config, Set.of());
    Assumptions.assumeTrue(
        elsewhere != null, "a core of this media runs every service it declares");
    Recording notHosted = new Recording(1);
    Recording hosted = new Recording(3);
    PrimeCore host = newCoreHosting(config, Set.of("driver"));
    try {
      elsewhere.service("driver", notHosted);
      host.service("driver", hosted);
      elsewhere.start(); // first: had it launched the service, it would run while the host works
      host.start();
      assertTrue(await(hosted.worked), "the host runs it; works: " + hosted.works.get());
      assertEquals(Set.of("driver"), elsewhere.topology().hostedElsewhere());
      assertFalse(elsewhere.serviceNames().contains("driver"), elsewhere.serviceNames().toString());
      assertTrue(host.serviceNames().contains("driver"), host.serviceNames().toString());
      assertEquals(0, notHosted.initializations.get(), "the other process does not run it");
      assertEquals(0, notHosted.works.get());
      elsewhere.close();
      assertEquals(0, hosted.shutdowns.get(), "closing the other process leaves it running");
      CountDownLatch more = new CountDownLatch(2);
      hosted.nextWorks = more;
      assertTrue(await(more), "the host goes on working");
    } finally {
      elsewhere.close();
      host.close();
    }
    assertEquals(1, hosted.initializations.get());
    assertEquals(1, hosted.shutdowns.get());
    assertEquals(0, notHosted.initializations.get());
    assertEquals(0, notHosted.shutdowns.get());
  }

  /**
   * {@code shutdown()} runs only if {@code initialize()} succeeded: a service whose initialize
   * fails until the core closes is never shut down, never works, and the close still returns
   * promptly and leaves no thread (architecture, <i>Generic services</i>, "Start and stop").
   */
  @Test
  default void aServiceWhoseInitializeNeverSucceededIsNotShutDown() throws InterruptedException {
    List<Failure> failures = new CopyOnWriteArrayList<>();
    ErrorConformance.Boom absent = new ErrorConformance.Boom("no device");
    CountDownLatch tried = new CountDownLatch(2);
    Recording driver =
        new Recording(1) {
          @Override
          public void initialize() throws Exception {
            super.initialize();
            tried.countDown();
            throw absent;
          }
        };
    PrimeCore core = newCore(recordingFailures(failures));
    long began;
    try (core) {
      core.service("absent-driver", driver);
      core.start();
      assertTrue(await(tried), "initialize was tried again after its failure");
      began = System.nanoTime();
    }
    long closeMillis = TimeUnit.NANOSECONDS.toMillis(System.nanoTime() - began);
    assertTrue(
        closeMillis < core.config().shutdownTimeout().toMillis(),
        "close interrupted the back-off instead of waiting for the timeout: " + closeMillis + " ms");
    assertEquals(0, driver.works.get(), "no work without a successful initialize");
    assertEquals(0, driver.shutdowns.get(), "no shutdown without a successful initialize");
    for (Failure failure : failures) {
      assertEquals(
          new Failure("absent-driver", GenericService.Step.INITIALIZE, absent), failure, "only initialize failed");
    }
    assertNoThreadsLeft(core);
  }
}

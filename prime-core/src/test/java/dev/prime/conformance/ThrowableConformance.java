package dev.prime.conformance;

import static dev.prime.conformance.ConformanceBase.assertNoThreadsLeft;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTimeoutPreemptively;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.ChainFailedException;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import java.io.IOException;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.function.Supplier;
import org.junit.jupiter.api.Assumptions;
import org.junit.jupiter.api.Test;

/**
 * What a failure looks like, for every kind of throwable a block throws: a synchronous caller gets
 * a {@code ChainFailedException} naming the chain as the user named it, with the block's own
 * throwable as cause, for everything but a {@link VirtualMachineError}, which reaches it unwrapped
 * (promptly also where blocks run in services, which it then ends); the error handler of an
 * asynchronous service gets the chain's name, the input and the block's own throwable, and the
 * service goes on.
 */
public interface ThrowableConformance extends ConformanceBase {

  /** The throwables a block may throw that every media wraps (or reports) and survives. */
  private static List<Supplier<Throwable>> survivableFailures() {
    return List.of(
        () -> new IllegalStateException("a runtime exception"),
        () -> new IOException("a checked exception, thrown sneakily"),
        () -> new AssertionError("an assertion"),
        () -> new NoClassDefFoundError("an error that is no VirtualMachineError"));
  }

  /** Throws any throwable, checked or not, without declaring it. */
  @SuppressWarnings("unchecked")
  private static <E extends Throwable> RuntimeException sneaky(Throwable t) throws E {
    throw (E) t;
  }

  @Test
  default void everyThrowableButAVirtualMachineErrorReachesASyncCallerWrappedAndNamed() {
    for (Supplier<Throwable> failure : survivableFailures()) {
      Throwable thrown = failure.get();
      try (PrimeCore core = newCore()) {
        Chain<Integer, Integer> single =
            core.chain(
                "divide",
                x -> {
                  if (x == 0) {
                    throw sneaky(thrown);
                  }
                  return 100 / x;
                });
        Chain<Integer, Integer> linked =
            core.chain("scale", (Integer x) -> x - 5)
                .then(
                    core.chain(
                        "inner",
                        x -> {
                          if (x == 0) {
                            throw sneaky(thrown);
                          }
                          return x;
                        }));
        core.start();
        Block<Integer, Integer> block = single.toBlock();
        ChainFailedException e = assertThrows(ChainFailedException.class, () -> block.process(0));
        assertEquals("divide", e.chainName(), "for " + thrown);
        assertSame(thrown, e.getCause(), "the cause is the block's own throwable: " + e);
        assertEquals(50, block.process(2), "the chain works after a " + thrown);

        Block<Integer, Integer> linkedBlock = linked.toBlock();
        ChainFailedException inner =
            assertThrows(ChainFailedException.class, () -> linkedBlock.process(5));
        assertEquals("inner", inner.chainName(), "the innermost chain is named for " + thrown);
        assertSame(thrown, inner.getCause());
      }
    }
  }

  @Test
  default void aVirtualMachineErrorReachesASyncCallerUnwrapped() {
    Assumptions.assumeTrue(
        blocksRunOnTheCallersThread(),
        "this media runs blocks in services: see the test of a VirtualMachineError in a service");
    OutOfMemoryError oom = new OutOfMemoryError("thrown by a block on purpose");
    try (PrimeCore core = newCore()) {
      Chain<Integer, Integer> chain =
          core.chain(
              "vm",
              x -> {
                if (x == 0) {
                  throw oom;
                }
                return x < 0 ? recurseForever(x) : x;
              });
      core.start();
      Block<Integer, Integer> block = chain.toBlock();
      assertSame(oom, assertThrows(OutOfMemoryError.class, () -> block.process(0)));
      assertThrows(StackOverflowError.class, () -> block.process(-1));
      assertEquals(3, block.process(3), "the chain works after a VirtualMachineError");
    }
  }

  @Test
  default void aVirtualMachineErrorInAServiceReachesASyncCallerPromptlyAndEndsOnlyThatService() {
    Assumptions.assumeFalse(
        blocksRunOnTheCallersThread(),
        "this media runs blocks on the caller's thread: see the test of the unwrapped error");
    OutOfMemoryError oom = new OutOfMemoryError("thrown by a block on purpose");
    try (PrimeCore core = newCore()) {
      Block<Integer, Integer> vm =
          core.chain(
                  "vm",
                  (Integer x) -> {
                    if (x == 0) {
                      throw oom;
                    }
                    return x;
                  })
              .toBlock();
      Block<Integer, Integer> deep =
          core.chain("deep", (Integer x) -> x < 0 ? recurseForever(x) : x).toBlock();
      Block<Integer, Integer> other = core.chain("other", (Integer x) -> x + 1).toBlock();
      core.start();
      assertEquals(1, vm.process(1));
      // promptly: within the kit's patience, not at the media's call timeout
      OutOfMemoryError thrown =
          assertTimeoutPreemptively(
              patience(), () -> assertThrows(OutOfMemoryError.class, () -> vm.process(0)));
      assertSame(oom, thrown, "the block's own error, unwrapped, in the process that ran it");
      assertTimeoutPreemptively(
          patience(), () -> assertThrows(StackOverflowError.class, () -> deep.process(-1)));
      assertEquals(3, other.process(2), "the core's other services go on");
    }
  }

  /**
   * A {@link VirtualMachineError} a block throws in an asynchronous service ends that service only,
   * and not silently: the core logs an ERROR line {@code service '<name>' stops: <the error>},
   * naming the service as {@link PrimeCore#serviceNames()} lists it, the chain (the JVM itself is in trouble, so the error handler does not get it). The core's other
   * services of the same source go on with every value, and {@code close()} still stops them and
   * leaves no thread (architecture, <i>Errors</i>).
   */
  @Test
  default void aVirtualMachineErrorInAnAsyncServiceEndsOnlyThatServiceAndIsLogged()
      throws InterruptedException {
    OutOfMemoryError oom = new OutOfMemoryError("thrown by the block of 'fatal' on purpose");
    CopyOnWriteArrayList<Throwable> handled = new CopyOnWriteArrayList<>();
    CoreConfig config =
        CoreConfig.builder().errorHandler((service, input, error) -> handled.add(error)).build();
    PrimeCore core = newCore(config);
    List<String> stops = new ArrayList<>();
    try (CapturedStderr err = new CapturedStderr()) {
      try (core) {
        EventBlock<Integer> events = new EventBlock<>();
        dev.prime.Source<Integer> source = core.source("vm-input", events);
        source.then(
            core.chain(
                "fatal",
                (Integer x) -> {
                  if (x == 1) {
                    throw oom;
                  }
                  return x;
                }));
        source.then(core.chain("overflow", (Integer x) -> x == 1 ? recurseForever(x) : x));
        Reader<Integer> survivor = source.then(core.chain("survivor", (Integer x) -> x * 10)).reader();
        core.start();
        for (int i = 1; i <= 4; i++) {
          events.publish(i);
        }
        assertEquals(List.of(10, 20, 30, 40), takeOrFail(survivor, 4), "the other service went on");
        long deadline = System.nanoTime() + patience().toNanos();
        CountDownLatch never = new CountDownLatch(1);
        while (stops.size() < 2 && System.nanoTime() < deadline) {
          never.await(10, TimeUnit.MILLISECONDS); // a bounded pause while the lines are written
          stops.clear();
          for (String line : err.lines()) {
            if (line.contains("ERROR")
                && line.contains("stops")
                && (line.contains("service 'fatal' stops") && line.contains(oom.getMessage())
                    || line.contains("service 'overflow' stops")
                        && line.contains("StackOverflowError"))) {
              stops.add(line);
            }
          }
        }
      }
    }
    assertEquals(2, stops.size(), "one ERROR line for each service that stopped: " + stops);
    assertEquals(List.of(), handled, "a VirtualMachineError does not go to the error handler");
    assertNoThreadsLeft(core);
  }

  /**
   * {@link dev.prime.ErrorHandler}: "A {@link VirtualMachineError} the handler throws ends the
   * service, as one its block throws." A block throws an ordinary exception and the error handler
   * then throws an {@link OutOfMemoryError}: the core logs the ERROR line {@code service '<name>'
   * stops: <the error>} for that service (named after its chain, as in the test of an error its
   * block throws), which processes nothing more, while the core's other
   * service of the same source goes on with every value, and {@code close()} still stops it and
   * leaves no thread.
   */
  @Test
  default void aVirtualMachineErrorTheErrorHandlerThrowsEndsThatServiceLikeOneOfItsBlock()
      throws InterruptedException {
    OutOfMemoryError oom = new OutOfMemoryError("thrown by the error handler on purpose");
    CountDownLatch handled = new CountDownLatch(1);
    CoreConfig config =
        CoreConfig.builder()
            .errorHandler(
                (service, input, error) -> {
                  handled.countDown();
                  throw oom;
                })
            .build();
    List<Integer> doomedSaw = new CopyOnWriteArrayList<>();
    PrimeCore core = newCore(config);
    List<String> stops = new ArrayList<>();
    try (CapturedStderr err = new CapturedStderr()) {
      try (core) {
        EventBlock<Integer> events = new EventBlock<>();
        dev.prime.Source<Integer> source = core.source("handled-input", events);
        source.then(
            core.chain(
                "doomed",
                (Integer x) -> {
                  doomedSaw.add(x);
                  if (x == 1) {
                    throw new IllegalStateException("the block of 'doomed' fails on 1");
                  }
                  return x;
                }));
        Reader<Integer> bystander =
            source.then(core.chain("bystander", (Integer x) -> x * 10)).reader();
        core.start();
        events.publish(1);
        assertTrue(
            handled.await(patience().toMillis(), TimeUnit.MILLISECONDS), "the handler was called");
        long deadline = System.nanoTime() + patience().toNanos();
        CountDownLatch never = new CountDownLatch(1);
        while (stops.isEmpty() && System.nanoTime() < deadline) {
          never.await(10, TimeUnit.MILLISECONDS); // a bounded pause while the line is written
          for (String line : err.lines()) {
            if (line.contains("ERROR")
                && line.contains("service 'doomed' stops")
                && line.contains(oom.getMessage())) {
              stops.add(line);
            }
          }
        }
        assertEquals(1, stops.size(), "one ERROR line: the service stopped: " + err.lines());
        for (int i = 2; i <= 4; i++) {
          events.publish(i);
        }
        assertEquals(List.of(10, 20, 30, 40), takeOrFail(bystander, 4), "the other service went on");
        assertEquals(List.of(1), doomedSaw, "the ended service processed nothing more");
      }
    }
    assertNoThreadsLeft(core);
  }

  /** Overflows the stack. */
  private static int recurseForever(int depth) {
    return recurseForever(depth - 1) + 1;
  }

  @Test
  default void theErrorHandlerGetsTheChainsNameTheInputAndTheBlocksOwnThrowable()
      throws InterruptedException {
    List<Throwable> failures = new ArrayList<>();
    for (Supplier<Throwable> failure : survivableFailures()) {
      failures.add(failure.get());
    }
    CopyOnWriteArrayList<String> services = new CopyOnWriteArrayList<>();
    CopyOnWriteArrayList<Object> inputs = new CopyOnWriteArrayList<>();
    CopyOnWriteArrayList<Throwable> errors = new CopyOnWriteArrayList<>();
    CountDownLatch reported = new CountDownLatch(failures.size() + 1);
    CoreConfig config =
        CoreConfig.builder()
            .errorHandler(
                (service, input, error) -> {
                  services.add(service);
                  inputs.add(input);
                  errors.add(error);
                  reported.countDown();
                })
            .build();
    try (PrimeCore core = newCore(config)) {
      EventBlock<Integer> imu = new EventBlock<>();
      EventBlock<Integer> wheels = new EventBlock<>();
      Reader<Integer> out =
          core.link(
                  core.source("imu", imu),
                  core.chain(
                      "divide",
                      x -> {
                        if (x < 0) {
                          throw sneaky(failures.get(-x - 1));
                        }
                        return x * 10;
                      }))
              .reader();
      Throwable innerFailure = new ArithmeticException("inner fails");
      Reader<Integer> linkedOut =
          core.link(
                  core.source("wheels", wheels),
                  core.chain("offset", (Integer x) -> x - 5)
                      .then(
                          core.chain(
                              "ratio",
                              x -> {
                                if (x == 0) {
                                  throw sneaky(innerFailure);
                                }
                                return x;
                              })))
              .reader();
      core.start();
      List<Integer> expectedInputs = new ArrayList<>();
      for (int i = 1; i <= failures.size(); i++) {
        imu.publish(-i);
        imu.publish(i);
        expectedInputs.add(-i);
      }
      List<Integer> expectedOut = new ArrayList<>();
      for (int i = 1; i <= failures.size(); i++) {
        expectedOut.add(i * 10);
      }
      assertEquals(expectedOut, takeOrFail(out, failures.size()), "the service went on");
      wheels.publish(5);
      wheels.publish(6);
      assertEquals(1, takeOrFail(linkedOut), "the linked service went on");
      assertTrue(reported.await(patience().toMillis(), TimeUnit.MILLISECONDS));

      for (int i = 0; i < failures.size(); i++) {
        assertEquals("divide", services.get(i), "the chain's name as the user named it");
        assertEquals(expectedInputs.get(i), inputs.get(i));
        assertSame(failures.get(i), errors.get(i), "the block's own throwable, not a wrapper");
      }
      int last = failures.size();
      assertEquals("ratio", services.get(last), "the chain of a linked chain that failed");
      assertSame(innerFailure, errors.get(last));
      assertEquals(
          servicesOfLinkedChain(2) == 1 ? 5 : 0,
          inputs.get(last),
          "fused media give the service's input, Optimus the failing chain's own input");
    }
  }

  @Test
  default void anErrorInAListenerIsReportedAndTheListenerGoesOn() throws InterruptedException {
    AssertionError assertion = new AssertionError("listener fails");
    CopyOnWriteArrayList<Throwable> errors = new CopyOnWriteArrayList<>();
    CountDownLatch reported = new CountDownLatch(1);
    CountDownLatch second = new CountDownLatch(1);
    CoreConfig config =
        CoreConfig.builder()
            .errorHandler(
                (service, input, error) -> {
                  errors.add(error);
                  reported.countDown();
                })
            .build();
    try (PrimeCore core = newCore(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      core.source(events)
          .listen(
              x -> {
                if (x == 1) {
                  throw assertion;
                }
                second.countDown();
              });
      core.start();
      events.publish(1);
      events.publish(2);
      assertTrue(second.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      assertTrue(reported.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      assertInstanceOf(AssertionError.class, errors.get(0));
      assertSame(assertion, errors.get(0));
    }
  }
}

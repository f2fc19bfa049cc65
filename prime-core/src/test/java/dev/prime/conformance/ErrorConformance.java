package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.ChainFailedException;
import dev.prime.CoreClosedException;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Source;
import java.util.Arrays;
import java.util.List;
import java.util.Set;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.CountDownLatch;
import java.util.Map;
import java.util.concurrent.ConcurrentHashMap;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicReference;
import org.junit.jupiter.api.Test;

/** Errors: a failing block names its chain to sync callers, and async services survive it. */
public interface ErrorConformance extends ConformanceBase {

  /** A failure a test provokes on purpose. */
  final class Boom extends RuntimeException {
    private static final long serialVersionUID = 1L;

    Boom(String message) {
      super(message);
    }
  }

  @Test
  default void syncFailureNamesTheInnermostChain() {
    Boom boom = new Boom("bad value");
    try (PrimeCore core = newCore()) {
      Chain<Integer, Integer> failing =
          core.chain(
              "failing",
              x -> {
                throw boom;
              });
      Chain<List<Integer>, Integer> outer =
          core.link(
              core.forEach(core.link(core.chain("first", (Integer x) -> x + 1), failing)),
              core.chain("last", (List<Integer> l) -> l.size()));
      core.start();
      Block<List<Integer>, Integer> block = outer.toBlock();
      ChainFailedException e =
          assertThrows(ChainFailedException.class, () -> block.process(List.of(1)));
      assertEquals("failing", e.chainName());
      assertTrue(e.getMessage().contains("failing"), e.getMessage());
      assertSame(boom, e.getCause());
    }
  }

  @Test
  default void syncFailureOfASingleChain() {
    try (PrimeCore core = newCore()) {
      Chain<String, Integer> parse = core.chain("parse", Integer::parseInt);
      core.start();
      Block<String, Integer> block = parse.toBlock();
      assertEquals(12, block.process("12"));
      ChainFailedException e = assertThrows(ChainFailedException.class, () -> block.process("x"));
      assertEquals("parse", e.chainName());
      assertTrue(e.getCause() instanceof NumberFormatException, String.valueOf(e.getCause()));
      assertEquals(13, block.process("13"), "a chain keeps working after a failure");
    }
  }

  /**
   * {@link dev.prime.ErrorHandler#handle}: the input is the value that entered the linked chain on
   * a media that fuses linked chains, the value that entered the failing chain on one that runs
   * each chain as a service of its own ({@link #servicesOfLinkedChain}). The second of two linked
   * chains on a source gets a {@code null} from the first (chains pass {@code null} between
   * blocks) and throws on it: the handler gets the failing chain's name, the block's own exception
   * and, as input, the value published (fused) or that {@code null} (one service per chain), and
   * the service goes on.
   */
  @Test
  default void theErrorHandlerGetsTheInputOfTheLinkedOrOfTheFailingChainEvenANull()
      throws InterruptedException {
    List<String> reports = new CopyOnWriteArrayList<>();
    CountDownLatch reported = new CountDownLatch(1);
    CoreConfig config =
        CoreConfig.builder()
            .errorHandler(
                (service, input, error) -> {
                  reports.add(service + " on " + input + ": " + error.getMessage());
                  reported.countDown();
                })
            .build();
    try (PrimeCore core = newCore(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> out =
          core.source("numbers", events)
              .then(
                  core.chain("maybe", (Integer x) -> x > 0 ? x : null)
                      .then(
                          core.chain(
                              "strict",
                              (Integer x) -> {
                                if (x == null) {
                                  throw new Boom("got null");
                                }
                                return x * 10;
                              })))
              .reader();
      core.start();
      events.publish(-5);
      events.publish(2);
      assertEquals(20, takeOrFail(out), "the service goes on");
      assertTrue(reported.await(patience().toMillis(), TimeUnit.MILLISECONDS), "reported");
      String input = servicesOfLinkedChain(2) == 1 ? "-5" : "null";
      assertEquals(List.of("strict on " + input + ": got null"), reports);
    }
  }

  @Test
  default void asyncFailureGoesToTheErrorHandlerAndTheServiceGoesOn() throws InterruptedException {
    CopyOnWriteArrayList<Object> failedInputs = new CopyOnWriteArrayList<>();
    CopyOnWriteArrayList<Throwable> errors = new CopyOnWriteArrayList<>();
    CountDownLatch reported = new CountDownLatch(2);
    CoreConfig config =
        CoreConfig.builder()
            .errorHandler(
                (service, input, error) -> {
                  failedInputs.add(input);
                  errors.add(error);
                  reported.countDown();
                })
            .build();
    try (PrimeCore core = newCore(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> out =
          core.link(
                  core.source(events),
                  core.chain(
                      "picky",
                      (Integer x) -> {
                        if (x % 3 == 0) {
                          throw new Boom("no multiples of 3: " + x);
                        }
                        return x;
                      }))
              .reader();
      core.start();
      for (int i = 1; i <= 7; i++) {
        events.publish(i);
      }
      assertEquals(List.of(1, 2, 4, 5, 7), takeOrFail(out, 5));
      assertTrue(reported.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      assertEquals(List.of(3, 6), failedInputs);
      for (Throwable error : errors) {
        assertTrue(error instanceof Boom, "the handler gets the block's own exception: " + error);
      }
    }
  }

  /**
   * {@link dev.prime.ErrorHandler}: "An exception thrown by the handler itself is logged and
   * ignored". The service goes on, and the core logs one ERROR line {@code the error handler
   * failed for service '<name>'} with the handler's exception, the block's failure suppressed in
   * it, so neither is lost.
   */
  @Test
  default void failingErrorHandlerDoesNotKillTheService() throws InterruptedException {
    CoreConfig config =
        CoreConfig.builder()
            .errorHandler(
                (service, input, error) -> {
                  throw new Boom("handler fails too");
                })
            .build();
    try (CapturedStderr err = new CapturedStderr()) {
      try (PrimeCore core = newCore(config)) {
        assertEquals(2, secondValueAfterFirstFails(core, new Boom("first fails")));
      }
      List<String> lines = err.lines();
      assertTrue(
          lines.stream()
              .anyMatch(l -> l.contains("ERROR") && l.contains("the error handler failed for service")),
          "the handler's failure is logged at ERROR: " + lines);
      assertTrue(
          lines.stream().anyMatch(l -> l.contains("Boom: handler fails too")),
          "with the handler's exception: " + lines);
      assertTrue(
          lines.stream().anyMatch(l -> l.contains("Suppressed") && l.contains("Boom: first fails")),
          "and the block's failure suppressed in it: " + lines);
    }
  }

  @Test
  default void closedCoreExceptionFromAnotherCoreDoesNotStopTheService()
      throws InterruptedException {
    CopyOnWriteArrayList<Object> failedInputs = new CopyOnWriteArrayList<>();
    CoreConfig config =
        CoreConfig.builder().errorHandler((service, input, error) -> failedInputs.add(input)).build();
    try (PrimeCore core = newCore(config)) {
      assertEquals(
          2,
          secondValueAfterFirstFails(core, new dev.prime.CoreClosedException("some-other-core")),
          "the service went on after the failure");
      assertEquals(List.of(1), failedInputs);
    }
  }

  /**
   * Links a chain that throws {@code failure} on the value 1 to a source, starts the core,
   * publishes 1 then 2, and returns what the service published next.
   */
  private Integer secondValueAfterFirstFails(PrimeCore core, RuntimeException failure)
      throws InterruptedException {
    EventBlock<Integer> events = new EventBlock<>();
    Reader<Integer> out =
        core.link(
                core.source(events),
                core.chain(
                    (Integer x) -> {
                      if (x == 1) {
                        throw failure;
                      }
                      return x;
                    }))
            .reader();
    core.start();
    events.publish(1);
    events.publish(2);
    return takeOrFail(out);
  }

  /**
   * A filter or flat-map whose block throws sends the failure to the error handler under its
   * name in the topology ({@code filter(imu)}, {@code flatMap(imu)}), with the value it took as
   * the input and the block's own exception, and goes on with the next value (architecture,
   * <i>Errors</i>, "Services").
   */
  @Test
  default void aFailingFilterOrFlatMapIsReportedUnderItsNameWithTheValueAndGoesOn()
      throws InterruptedException {
    Boom filterFails = new Boom("the filter fails on 2");
    Boom flatMapFails = new Boom("the flat-map fails on 2");
    List<List<Object>> reports = new CopyOnWriteArrayList<>();
    CountDownLatch reported = new CountDownLatch(2);
    CoreConfig config =
        CoreConfig.builder()
            .errorHandler(
                (service, input, error) -> {
                  reports.add(Arrays.asList(service, input, error));
                  reported.countDown();
                })
            .build();
    try (PrimeCore core = newCore(config)) {
      EventBlock<Integer> imu = new EventBlock<>();
      Source<Integer> source = core.source("imu", imu);
      Reader<Integer> passed =
          source
              .filter(
                  x -> {
                    if (x == 2) {
                      throw filterFails;
                    }
                    return true;
                  })
              .reader();
      Reader<Integer> made =
          source
              .flatMap(
                  (Integer x) -> {
                    if (x == 2) {
                      throw flatMapFails;
                    }
                    return List.of(x, x);
                  })
              .reader();
      core.start();
      imu.publish(1);
      imu.publish(2);
      imu.publish(3);
      assertEquals(List.of(1, 3), takeOrFail(passed, 2), "the filter went on after 2");
      assertEquals(List.of(1, 1, 3, 3), takeOrFail(made, 4), "the flat-map went on after 2");
      assertTrue(reported.await(patience().toMillis(), TimeUnit.MILLISECONDS), "reports: " + reports);
      assertEquals(
          Set.of(
              Arrays.asList("filter(imu)", 2, filterFails),
              Arrays.asList("flatMap(imu)", 2, flatMapFails)),
          Set.copyOf(reports));
    }
  }

  /**
   * {@link Block}: "A {@link ChainFailedException} or {@link CoreClosedException} thrown by a
   * block (it called another chain) passes unchanged". A synchronous caller of a chain whose block
   * calls another chain that fails gets the failure of that other chain, naming it, with its
   * block's own exception as the cause, not one naming the calling chain; a {@link
   * CoreClosedException} a block throws reaches the caller as such, not wrapped.
   */
  @Test
  default void aChainFailureOrClosedCoreThrownByABlockReachesTheCallerUnchanged() {
    Boom boom = new Boom("the called chain refuses");
    CoreClosedException closed = new CoreClosedException("another-core");
    try (PrimeCore core = newCore()) {
      Chain<Integer, Integer> called =
          core.chain(
              "called",
              (Integer x) -> {
                if (x < 0) {
                  throw boom;
                }
                return x;
              });
      AtomicReference<Block<Integer, Integer>> calledBlock = new AtomicReference<>();
      Chain<Integer, Integer> caller =
          core.chain("caller", (Integer x) -> calledBlock.get().process(x) + 1);
      Chain<Integer, Integer> closedCaller =
          core.chain(
              "closed-caller",
              (Integer x) -> {
                throw closed;
              });
      core.start();
      calledBlock.set(called.toBlock());
      Block<Integer, Integer> block = caller.toBlock();
      assertEquals(6, block.process(5));
      ChainFailedException failed =
          assertThrows(ChainFailedException.class, () -> block.process(-1));
      assertEquals("called", failed.chainName(), "the failing chain is named: " + failed);
      assertSame(boom, failed.getCause(), "the cause is the called block's own: " + failed);
      Block<Integer, Integer> closedBlock = closedCaller.toBlock();
      RuntimeException refused = assertThrows(RuntimeException.class, () -> closedBlock.process(1));
      assertInstanceOf(CoreClosedException.class, refused, "passed on unwrapped");
      assertTrue(refused.getMessage().contains("another-core"), refused.getMessage());
    }
  }
  /**
   * A value of the wrong type that reaches a block through a raw or unchecked cast fails in the
   * block that takes it, as that block's own {@link ClassCastException}, never earlier in the
   * media's code and never as another failure: a synchronous caller gets a {@link
   * ChainFailedException} naming that chain (in a linked chain, the first, whose block took the
   * value), and a service reports it to the error handler with the chain's name and the value,
   * and goes on with the next value.
   */
  @Test
  @SuppressWarnings({"unchecked", "rawtypes"})
  default void aValueOfTheWrongTypeFailsInTheBlockThatTakesItAndNamesItsChain()
      throws InterruptedException {
    List<List<Object>> reports = new CopyOnWriteArrayList<>();
    CountDownLatch reported = new CountDownLatch(1);
    CoreConfig config =
        CoreConfig.builder()
            .errorHandler(
                (service, input, error) -> {
                  reports.add(Arrays.asList(service, input, error.getClass()));
                  reported.countDown();
                })
            .build();
    try (PrimeCore core = newCore(config)) {
      Chain<Integer, Integer> increment = core.chain("increment", (Integer x) -> x + 1);
      Chain<Integer, Integer> linked =
          core.chain("describe", (Integer x) -> "n" + x)
              .then(core.chain("length", (String s) -> s.length()));
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> halves =
          core.source("typed", events).then(core.chain("halve", (Integer x) -> x / 2)).reader();
      core.start();
      Block raw = increment.toBlock();
      ChainFailedException single =
          assertThrows(ChainFailedException.class, () -> raw.process("seven"));
      assertEquals("increment", single.chainName(), single.getMessage());
      assertInstanceOf(ClassCastException.class, single.getCause(), single.toString());
      assertTrue(
          single.getMessage().contains("'increment'")
              && single.getMessage().contains(String.class.getName()),
          "names the chain and the wrong type: " + single.getMessage());
      assertEquals(8, raw.process(7), "the chain works after the wrong value");
      Block rawLinked = linked.toBlock();
      ChainFailedException first =
          assertThrows(ChainFailedException.class, () -> rawLinked.process("seven"));
      assertEquals("describe", first.chainName(), first.getMessage());
      assertInstanceOf(ClassCastException.class, first.getCause(), first.toString());
      ((EventBlock) events).publish("eight");
      events.publish(8);
      assertEquals(4, takeOrFail(halves), "the service went on after the wrong value");
      assertTrue(reported.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      assertEquals(List.of(Arrays.asList("halve", "eight", ClassCastException.class)), reports);
    }
  }

  /**
   * {@link dev.prime.ErrorHandler}: "Called on the service's thread": the handler runs on the
   * thread the failing logic ran on, for a chain linked to a source and for a listener, not on a
   * thread of its own or the publisher's.
   */
  @Test
  default void theErrorHandlerIsCalledOnTheThreadOfTheServiceThatFailed()
      throws InterruptedException {
    Map<String, Thread> failedOn = new ConcurrentHashMap<>();
    Map<String, Thread> handledOn = new ConcurrentHashMap<>();
    CountDownLatch handled = new CountDownLatch(2);
    CoreConfig config =
        CoreConfig.builder()
            .errorHandler(
                (service, input, error) -> {
                  handledOn.put(error.getMessage(), Thread.currentThread());
                  handled.countDown();
                })
            .build();
    try (PrimeCore core = newCore(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("numbers", events);
      core.link(
          source,
          core.chain(
              "fails",
              (Integer x) -> {
                failedOn.put("chain", Thread.currentThread());
                throw new Boom("chain");
              }));
      source.listen(
          x -> {
            failedOn.put("listener", Thread.currentThread());
            throw new Boom("listener");
          });
      core.start();
      events.publish(1);
      assertTrue(
          handled.await(patience().toMillis(), TimeUnit.MILLISECONDS),
          "both failures reached the handler: " + handledOn.keySet());
      for (String service : List.of("chain", "listener")) {
        assertSame(
            failedOn.get(service),
            handledOn.get(service),
            "the " + service + "'s failure was handled on its service's thread "
                + failedOn.get(service) + ", not on " + handledOn.get(service));
      }
    }
  }
}

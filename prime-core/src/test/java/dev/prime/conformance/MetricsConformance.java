package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.GenericService;
import dev.prime.Metrics;
import dev.prime.PrimeCore;
import dev.prime.ProcessingTimes;
import dev.prime.Reader;
import dev.prime.ServiceMetrics;
import dev.prime.Source;
import dev.prime.Tick;
import dev.prime.Tuple2;
import dev.prime.VirtualClock;
import java.time.Duration;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.List;
import java.util.Collections;
import java.util.concurrent.BlockingQueue;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.LinkedBlockingQueue;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicLong;
import java.util.function.Predicate;
import org.junit.jupiter.api.Test;

/**
 * Metrics (see {@link Metrics}): per metered node of the diagram, values in and out, failures,
 * dead letters, queue depth and processing times, read as snapshots under the topology's names,
 * the same on every media; off by default, and then nothing is compiled in.
 */
public interface MetricsConformance extends ConformanceBase {

  /**
   * Whether a value on which a service of a source threw is kept as a dead letter (Optimus); on
   * the other media dead letters are always 0.
   */
  default boolean failedServiceValuesAreDeadLettered() {
    return false;
  }

  /** A core with metrics on and failures collected (not logged). */
  default PrimeCore meteredCore(List<Throwable> failures) {
    return newCore(
        CoreConfig.builder()
            .metrics(true)
            .errorHandler((service, input, error) -> failures.add(error))
            .build());
  }

  @Test
  default void countsValuesThroughAChainAndASourceServiceExactly() throws Exception {
    int n = 20;
    List<Throwable> failures = Collections.synchronizedList(new ArrayList<>());
    try (PrimeCore core = meteredCore(failures)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> doubled =
          core.source("numbers", events).then(core.chain("double", (Integer x) -> x * 2));
      Reader<Integer> quadruples = doubled.filter(x -> x % 4 == 0).reader();
      Block<String, Integer> length = core.chain("length", String::length).toBlock();
      core.start();
      for (int i = 1; i <= n; i++) {
        events.publish(i);
      }
      List<Integer> out = takeOrFail(quadruples, n / 2);
      assertEquals(40, out.get(out.size() - 1)); // the last value passed: every one was tested
      for (String word : List.of("a", "bb", "ccc")) {
        assertEquals(word.length(), length.process(word));
      }

      Metrics metrics = core.metrics();
      assertSame(metrics, core.metrics(), "one metrics object per core");
      assertEquals(core.name(), metrics.core());
      assertCounts(metrics.service("numbers"), "EventSource", n, n, 0);
      assertCounts(metrics.service("double"), "BlockChain", n, n, 0);
      assertCounts(metrics.service("filter(numbers>double)"), "Filter", n, n / 2, 0);
      assertCounts(metrics.service("length"), "BlockChain", 3, 3, 0);
      assertEquals(0, metrics.service("filter(numbers>double)").queueDepth(), "all taken");
      assertEquals(-1, metrics.service("numbers").queueDepth(), "a source has no input queue");
      if (blocksRunOnTheCallersThread()) {
        // the in-memory media run a chain in its caller's thread or in the service it is linked
        // into: no queue of its own (Optimus reads each chain's lists)
        assertEquals(-1, metrics.service("double").queueDepth(), "a chain linked to a source");
        assertEquals(-1, metrics.service("length").queueDepth(), "a chain called directly");
      }
      for (ServiceMetrics service : metrics.services()) {
        assertEquals(0, service.deadLetters(), service.toString());
        assertEquals(0, service.missed(), service.toString());
        assertEquals(service.queueDepth() >= 0, metrics.hasQueue(service.name()),
            "hasQueue agrees with a queue depth read now: " + service);
      }
      assertTrue(metrics.hasQueue("filter(numbers>double)"), "a filter's input is a queue");
      assertFalse(metrics.hasQueue("numbers"), "a source has no input queue");
      assertEquals(!blocksRunOnTheCallersThread(), metrics.hasQueue("double"));
      assertEquals(!blocksRunOnTheCallersThread(), metrics.hasQueue("length"));
      IllegalArgumentException unknown =
          assertThrows(IllegalArgumentException.class, () -> metrics.hasQueue("no-such-node"));
      assertTrue(unknown.getMessage().contains("no-such-node"), unknown.getMessage());
      assertEquals(List.of(), failures);
    }
  }

  /**
   * {@link Metrics}: a chain's "in = calls, out = non-null results": a chain whose block returns
   * {@code null} for even inputs counts every call in and only its non-null results out, whether
   * it runs linked to a source or is called through its {@code toBlock()}; a {@code null} is not
   * a failure.
   */
  @Test
  default void aChainCountsItsNullResultsInButNotOut() throws Exception {
    List<Throwable> failures = Collections.synchronizedList(new ArrayList<>());
    try (PrimeCore core = meteredCore(failures)) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> odd =
          core.source("numbers", events)
              .then(core.chain("linked", (Integer x) -> x % 2 == 0 ? null : x))
              .reader();
      Block<Integer, Integer> called =
          core.chain("called", (Integer x) -> x % 2 == 0 ? null : x).toBlock();
      core.start();
      for (int i = 1; i <= 5; i++) {
        events.publish(i);
      }
      assertEquals(List.of(1, 3, 5), takeOrFail(odd, 3));
      for (int i = 1; i <= 4; i++) {
        assertEquals(i % 2 == 0 ? null : i, called.process(i));
      }
      Metrics metrics = core.metrics();
      assertCounts(metrics.service("linked"), "BlockChain", 5, 3, 0);
      assertCounts(metrics.service("called"), "BlockChain", 4, 2, 0);
      assertEquals(List.of(), failures);
    }
  }

  @Test
  default void failuresAreCountedWhenABlockThrows() throws Exception {
    int n = 10;
    List<Throwable> handled = Collections.synchronizedList(new ArrayList<>());
    try (PrimeCore core = meteredCore(handled)) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> evens =
          core.source("numbers", events)
              .then(
                  core.chain(
                      "picky",
                      (Integer x) -> {
                        if (x % 2 == 1) {
                          throw new IllegalArgumentException("odd: " + x);
                        }
                        return x;
                      }))
              .reader();
      Block<Integer, Integer> called =
          core.chain(
                  "called",
                  (Integer x) -> {
                    if (x < 0) {
                      throw new IllegalArgumentException("negative: " + x);
                    }
                    return x;
                  })
              .toBlock();
      core.start();
      for (int i = 1; i <= n; i++) {
        events.publish(i);
      }
      assertEquals(List.of(2, 4, 6, 8, 10), takeOrFail(evens, n / 2));
      assertEquals(1, called.process(1));
      assertThrows(RuntimeException.class, () -> called.process(-1));
      assertThrows(RuntimeException.class, () -> called.process(-2));

      Metrics metrics = core.metrics();
      ServiceMetrics picky = metrics.service("picky");
      assertCounts(picky, "BlockChain", n, n / 2, n / 2);
      assertEquals(failedServiceValuesAreDeadLettered() ? n / 2 : 0, picky.deadLetters());
      assertCounts(metrics.service("called"), "BlockChain", 3, 1, 2);
      assertEquals(n / 2, handled.size(), "the error handler saw the service's failures");
    }
  }

  /**
   * A block or filter that throws a checked exception without declaring it (as Kotlin code does,
   * an {@code IOException} of a sensor) fails like any other ({@link Block}): it is counted as a
   * failure and timed, and its value no longer counts as in progress in the queue depth.
   */
  @Test
  default void aCheckedExceptionThrownSneakilyIsCountedAsAFailure() throws Exception {
    List<Throwable> handled = Collections.synchronizedList(new ArrayList<>());
    try (PrimeCore core = meteredCore(handled)) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> evens =
          core.source("numbers", events)
              .filter(
                  x -> {
                    if (x % 2 == 1) {
                      throw MetricsConformance.<RuntimeException>sneaky(
                          new java.io.IOException("odd: " + x));
                    }
                    return true;
                  })
              .reader();
      Block<Integer, Integer> reads =
          core.chain(
                  "reads",
                  (Integer x) -> {
                    if (x < 0) {
                      throw MetricsConformance.<RuntimeException>sneaky(
                          new java.io.IOException("sensor unplugged"));
                    }
                    return x;
                  })
              .toBlock();
      core.start();
      for (int i = 1; i <= 4; i++) {
        events.publish(i);
      }
      assertEquals(List.of(2, 4), takeOrFail(evens, 2));
      assertEquals(1, reads.process(1));
      assertThrows(RuntimeException.class, () -> reads.process(-1));

      Metrics metrics = core.metrics();
      assertCounts(metrics.service("reads"), "BlockChain", 2, 1, 1);
      ServiceMetrics filter = metrics.service("filter(numbers)");
      assertCounts(filter, "Filter", 4, 2, 2);
      assertEquals(0, filter.queueDepth(), "nothing waits or is in progress: " + filter);
      assertEquals(2, handled.size(), "the error handler saw the filter's failures");
    }
  }

  @Test
  default void queueDepthCountsWhatWaitsAndWhatIsInProgress() throws Exception {
    CountDownLatch firstInside = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    try (PrimeCore core = meteredCore(Collections.synchronizedList(new ArrayList<>()))) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> passed =
          core.source("numbers", events)
              .filter(
                  x -> {
                    firstInside.countDown();
                    try {
                      return release.await(patience().toMillis(), TimeUnit.MILLISECONDS);
                    } catch (InterruptedException e) {
                      Thread.currentThread().interrupt();
                      return false;
                    }
                  })
              .reader();
      core.start();
      for (int i = 1; i <= 4; i++) {
        events.publish(i);
      }
      assertTrue(firstInside.await(patience().toMillis(), TimeUnit.MILLISECONDS));
      ServiceMetrics stuck = core.metrics().service("filter(numbers)");
      assertEquals(4, stuck.queueDepth(), "3 waiting and 1 in progress: " + stuck);
      assertEquals(1, stuck.valuesIn(), stuck.toString());
      release.countDown();
      assertEquals(List.of(1, 2, 3, 4), takeOrFail(passed, 4));
      ServiceMetrics done = core.metrics().service("filter(numbers)");
      assertEquals(0, done.queueDepth(), done.toString());
      assertEquals(4, done.valuesOut(), done.toString());
    }
  }

  @Test
  default void anEventSourceCountsWhatItsReadersMissed() throws Exception {
    try (PrimeCore core =
        newCore(CoreConfig.builder().metrics(true).sourceRetention(4).build())) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> late = core.source("numbers", events).reader();
      core.start();
      for (int i = 1; i <= 10; i++) {
        events.publish(i);
      }
      assertEquals(7, takeOrFail(late), "the oldest retained value");
      assertEquals(6, late.missed());
      ServiceMetrics numbers = core.metrics().service("numbers");
      assertEquals(6, numbers.missed(), numbers.toString());
      assertEquals(10, numbers.valuesOut(), numbers.toString());
    }
  }

  @Test
  default void metricsAndRecordingWorkTogether() throws Exception {
    CoreConfig config =
        CoreConfig.builder().metrics(true).recording(dev.prime.RecordingOptions.ring(10)).build();
    try (PrimeCore core = newCore(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> out =
          core.source("numbers", events).then(core.chain("inc", (Integer x) -> x + 1)).reader();
      core.start();
      for (int i = 1; i <= 3; i++) {
        events.publish(i);
      }
      assertEquals(List.of(2, 3, 4), takeOrFail(out, 3));
      assertEquals(List.of(1, 2, 3), core.recording().getAll("numbers"));
      assertEquals(List.of(2, 3, 4), core.recording().getAll("inc"));
      assertCounts(core.metrics().service("numbers"), "EventSource", 3, 3, 0);
      assertCounts(core.metrics().service("inc"), "BlockChain", 3, 3, 0);
    }
  }

  @Test
  default void aClosedCoreCountsNothingPublishedAfterClose() throws Exception {
    EventBlock<Integer> events = new EventBlock<>();
    Metrics metrics;
    try (PrimeCore core = meteredCore(Collections.synchronizedList(new ArrayList<>()))) {
      Reader<Integer> numbers = core.source("numbers", events).reader();
      core.start();
      for (int i = 1; i <= 3; i++) {
        events.publish(i);
      }
      assertEquals(List.of(1, 2, 3), takeOrFail(numbers, 3));
      metrics = core.metrics();
      assertCounts(metrics.service("numbers"), "EventSource", 3, 3, 0);
    }
    for (int i = 4; i <= 5; i++) {
      events.publish(i); // no subscriber of the closed core may count these
    }
    assertCounts(metrics.service("numbers"), "EventSource", 3, 3, 0);
  }

  /**
   * {@link Metrics}: a template chain's "processing = the time of each call (a template's includes
   * its parts')": an if/else whose chosen branch takes at least 5 ms, and a for-each over such a
   * body, each time every call at least as long as the part they ran, and in total at least the
   * total of their part.
   */
  @Test
  default void aTemplatesProcessingTimeIncludesItsParts() throws Exception {
    long sleepMillis = 5;
    long least = TimeUnit.MILLISECONDS.toNanos(sleepMillis);
    Block<Integer, Integer> work =
        x -> {
          try {
            Thread.sleep(sleepMillis); // the work whose time is measured
          } catch (InterruptedException e) {
            Thread.currentThread().interrupt();
          }
          return x;
        };
    try (PrimeCore core = meteredCore(Collections.synchronizedList(new ArrayList<>()))) {
      Block<Integer, Integer> choose =
          core.ifThenElse(
                  (Integer x) -> x > 0,
                  core.chain("slow-branch", work),
                  core.chain("fast-branch", (Integer x) -> x))
              .toBlock();
      Block<List<Integer>, List<Integer>> each =
          core.forEach(core.chain("slow-body", work)).toBlock();
      core.start();
      for (int i = 1; i <= 3; i++) {
        assertEquals(i, choose.process(i));
      }
      assertEquals(List.of(1, 2), each.process(List.of(1, 2)));
      Metrics metrics = core.metrics();
      ProcessingTimes ifElse = metrics.service("if(slow-branch|fast-branch)").processing();
      ProcessingTimes branch = metrics.service("slow-branch").processing();
      ProcessingTimes forEach = metrics.service("forEach(slow-body)").processing();
      ProcessingTimes body = metrics.service("slow-body").processing();
      assertEquals(3, ifElse.count(), ifElse.toString());
      assertEquals(1, forEach.count(), forEach.toString());
      assertTrue(ifElse.totalNanos() >= branch.totalNanos(), ifElse + " includes " + branch);
      assertTrue(ifElse.totalNanos() >= 3 * least, ifElse.toString());
      assertTrue(forEach.totalNanos() >= body.totalNanos(), forEach + " includes " + body);
      assertTrue(forEach.maxNanos() >= 2 * least, forEach.toString());
    }
  }

  @Test
  default void theHistogramTimesEveryValue() throws Exception {
    long sleepMillis = 5;
    try (PrimeCore core = meteredCore(Collections.synchronizedList(new ArrayList<>()))) {
      Block<Integer, Integer> slow =
          core.chain(
                  "slow",
                  (Integer x) -> {
                    try {
                      Thread.sleep(sleepMillis); // the work whose time is measured
                    } catch (InterruptedException e) {
                      Thread.currentThread().interrupt();
                    }
                    return x;
                  })
              .toBlock();
      core.start();
      for (int i = 0; i < 3; i++) {
        assertEquals(i, slow.process(i));
      }
      ProcessingTimes times = core.metrics().service("slow").processing();
      long least = TimeUnit.MILLISECONDS.toNanos(sleepMillis);
      assertEquals(3, times.count());
      assertEquals(3, Arrays.stream(times.bucketCounts()).sum());
      assertTrue(times.totalNanos() >= 3 * least, times.toString());
      assertTrue(times.maxNanos() >= least, times.toString());
      assertTrue(times.percentileNanos(0.5) >= least, times.toString());
      assertTrue(times.percentileNanos(1.0) <= times.maxNanos(), times.toString());
      assertTrue(times.meanNanos() >= least, times.toString());
    }
  }

  @Test
  default void templatesListenersAndFlatMapsAreMeteredUnderTheSameNamesOnEveryMedia()
      throws Exception {
    List<Throwable> failures = Collections.synchronizedList(new ArrayList<>());
    try (PrimeCore core = meteredCore(failures)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> numbers = core.source("numbers", "The numbers", events);
      AtomicLong heard = new AtomicLong();
      numbers.listen(x -> heard.incrementAndGet());
      Reader<Integer> pairs = numbers.flatMap(x -> List.of(x, x)).reader();
      Chain<Integer, String> parity =
          core.ifThenElse(
              x -> x % 2 == 0,
              core.chain("even", (Integer x) -> "even"),
              core.chain("odd", (Integer x) -> "odd"));
      Block<Integer, String> parityBlock =
          parity.then(core.chain("upper", "Upper case", String::toUpperCase)).toBlock();
      core.start();
      for (int i = 1; i <= 4; i++) {
        events.publish(i);
      }
      assertEquals(List.of(1, 1, 2, 2, 3, 3, 4, 4), takeOrFail(pairs, 8));
      assertEquals("ODD", parityBlock.process(1));
      assertEquals("EVEN", parityBlock.process(2));
      assertEquals("EVEN", parityBlock.process(4));

      Metrics metrics = core.metrics();
      assertEquals(
          List.of(
              "numbers",
              "listen(numbers)",
              "flatMap(numbers)",
              "even",
              "odd",
              "if(even|odd)",
              "upper"),
          metrics.names());
      assertEquals(
          metrics.names(), metrics.services().stream().map(ServiceMetrics::name).toList());
      assertCounts(metrics.service("flatMap(numbers)"), "FlatMap", 4, 8, 0);
      assertCounts(metrics.service("if(even|odd)"), "IfElse", 3, 3, 0);
      assertCounts(metrics.service("even"), "BlockChain", 2, 2, 0);
      assertCounts(metrics.service("odd"), "BlockChain", 1, 1, 0);
      assertCounts(metrics.service("upper"), "BlockChain", 3, 3, 0);
      assertEquals("Upper case", metrics.service("upper").pseudoname());
      assertEquals("Upper case", metrics.service("upper").label());
      assertEquals("The numbers", metrics.service("numbers").pseudoname());
      assertNull(metrics.service("even").pseudoname());
      assertEquals("even", metrics.service("even").label());

      // the listener runs after the flat-map's values were seen: wait until it timed all four
      // (it counts a value in when it takes it, and times it once it has run)
      ServiceMetrics listener =
          settled(core, "listen(numbers)", m -> m.valuesIn() >= 4 && m.processing().count() >= 4);
      assertCounts(listener, "Listener", 4, 0, 0);
      assertEquals(4, heard.get());
      assertEquals(List.of(), failures);
    }
  }

  @Test
  default void aListenerIsToldOfEveryValueProcessedWhileRegistered() throws Exception {
    try (PrimeCore core = meteredCore(Collections.synchronizedList(new ArrayList<>()))) {
      Block<Integer, Integer> negate =
          core.chain(
                  "negate",
                  (Integer x) -> {
                    if (x == 0) {
                      throw new IllegalArgumentException("zero");
                    }
                    return -x;
                  })
              .toBlock();
      List<Boolean> told = Collections.synchronizedList(new ArrayList<>());
      AtomicLong nanos = new AtomicLong();
      Metrics.Subscription subscription =
          core.metrics()
              .onProcessed(
                  "negate",
                  (time, failed) -> {
                    told.add(failed);
                    nanos.addAndGet(time);
                  });
      core.start();
      assertEquals(-1, negate.process(1));
      assertThrows(RuntimeException.class, () -> negate.process(0));
      assertEquals(-2, negate.process(2));
      assertEquals(List.of(false, true, false), told);
      assertEquals(core.metrics().service("negate").processing().totalNanos(), nanos.get());
      subscription.close();
      subscription.close();
      assertEquals(-3, negate.process(3));
      assertEquals(3, told.size(), "closed: not told any more");
      assertEquals(4, core.metrics().service("negate").processing().count());
    }
  }

  @Test
  default void anUnknownNameIsRefusedWithTheMeteredNames() {
    try (PrimeCore core = meteredCore(Collections.synchronizedList(new ArrayList<>()))) {
      core.source("numbers", new EventBlock<Integer>());
      core.chain("double", (Integer x) -> x * 2);
      IllegalArgumentException e =
          assertThrows(IllegalArgumentException.class, () -> core.metrics().service("tripple"));
      assertTrue(e.getMessage().contains("'tripple'"), e.getMessage());
      assertTrue(e.getMessage().contains("[numbers, double]"), e.getMessage());
      assertThrows(
          IllegalArgumentException.class,
          () -> core.metrics().onProcessed("tripple", (time, failed) -> {}));
    }
  }

  @Test
  default void metricsOffSaysHowToTurnThemOn() {
    try (PrimeCore core = newCore()) {
      core.chain("double", (Integer x) -> x * 2);
      IllegalStateException e = assertThrows(IllegalStateException.class, core::metrics);
      assertTrue(e.getMessage().contains("metrics are off"), e.getMessage());
      assertTrue(e.getMessage().contains("CoreConfig.builder().metrics(true)"), e.getMessage());
    }
  }

  @Test
  default void metricsOffCompileNoTapIntoAChain() throws Exception {
    for (boolean on : new boolean[] {false, true}) {
      try (PrimeCore core = newCore(CoreConfig.builder().metrics(on).build())) {
        List<String> stack = RunningStack.classesOfAChainIn(core);
        boolean tapped = stack.stream().anyMatch(c -> c.startsWith("dev.prime.MeteringPoints"));
        assertEquals(on, tapped, "metrics " + (on ? "on" : "off") + ", stack " + stack);
      }
    }
  }

  @Test
  default void aGenericServiceCountsItsWorkCallsAndFailures() throws Exception {
    List<Throwable> handled = Collections.synchronizedList(new ArrayList<>());
    BlockingQueue<String> jobs = new LinkedBlockingQueue<>();
    PrimeCore core = meteredCore(handled);
    try {
      core.service(
          "driver",
          new GenericService() {
            @Override
            public void work() throws Exception {
              if (jobs.take().equals("fail")) {
                throw new IllegalStateException("the device said no");
              }
            }

            @Override
            public Duration backoff(int failures) {
              return Duration.ZERO;
            }
          });
      core.start();
      jobs.addAll(List.of("ok", "fail", "ok"));
      // three calls done, the fourth waits for its job
      ServiceMetrics driver =
          settled(
              core,
              "driver",
              m ->
                  m.valuesOut() == 2
                      && m.failures() == 1
                      && m.valuesIn() == 4
                      && m.processing().count() == 3);
      assertEquals("GenericServiceNode", driver.kind(), driver.toString());
      assertEquals(4, driver.valuesIn(), driver.toString());
      assertEquals(3, driver.processing().count(), "the waiting call is not timed yet: " + driver);
      assertEquals(-1, driver.queueDepth(), "a generic service has no input queue: " + driver);
      assertFalse(core.metrics().hasQueue("driver"), "a generic service has no input queue");
      assertEquals(0, driver.deadLetters(), driver.toString());
      assertTrue(core.metrics().names().contains("driver"), core.metrics().names().toString());
      assertEquals(1, handled.size(), "the error handler saw the failure: " + handled);
    } finally {
      core.close();
    }
    assertEquals(1, handled.size(), "stopping is no failure: " + handled);
  }

  @Test
  default void aCombinatorCountsTheValuesItTookAndTheTuplesItPublished() throws Exception {
    List<Throwable> failures = Collections.synchronizedList(new ArrayList<>());
    try (PrimeCore core = meteredCore(failures)) {
      EventBlock<Integer> left = new EventBlock<>();
      EventBlock<Integer> right = new EventBlock<>();
      Source<Tuple2<Integer, Integer>> pairs =
          core.zip(core.source("left", left), core.source("right", right));
      Reader<Tuple2<Integer, Integer>> out = pairs.reader();
      core.start();
      for (int i = 1; i <= 3; i++) {
        left.publish(i);
      }
      right.publish(10);
      right.publish(20);
      assertEquals(List.of(new Tuple2<>(1, 10), new Tuple2<>(2, 20)), takeOrFail(out, 2));
      ServiceMetrics zip =
          settled(
              core,
              pairs.name(),
              m -> m.valuesIn() == 5 && m.valuesOut() == 2 && m.processing().count() == 5);
      assertCounts(zip, "Combinator", 5, 2, 0);
      assertEquals(-1, zip.queueDepth(), zip.toString());
      assertFalse(core.metrics().hasQueue(pairs.name()), "a combinator has no input queue");
      assertEquals(0, zip.deadLetters(), zip.toString());
      assertCounts(core.metrics().service("left"), "EventSource", 3, 3, 0);
      assertEquals(List.of(), failures);
    }
  }

  @Test
  default void aTimerCountsItsTicksOnAVirtualClock() throws Exception {
    VirtualClock clock = new VirtualClock();
    try (PrimeCore core = newCore(CoreConfig.builder().metrics(true).clock(clock).build())) {
      Reader<Tick> ticks = core.timer("beat", Duration.ofMillis(10)).reader();
      core.start();
      assertEquals(0, core.metrics().service("beat").valuesOut(), "virtual time stands still");
      clock.advance(Duration.ofSeconds(1));
      List<Tick> hundred = takeOrFail(ticks, 100);
      assertEquals(100, hundred.get(99).count());
      ServiceMetrics beat =
          settled(
              core,
              "beat",
              m -> m.valuesOut() == 100 && m.valuesIn() == 100 && m.processing().count() == 100);
      assertCounts(beat, "Timer", 100, 100, 0);
      assertEquals(-1, beat.queueDepth(), beat.toString());
      assertFalse(core.metrics().hasQueue("beat"), "a timer has no input queue");
      assertEquals(0, beat.deadLetters(), beat.toString());
    }
  }

  /**
   * The snapshot of {@code name} once {@code done} holds of it: what a service counts after it
   * handed its value on shows a little after the value arrives. Bounded in time and count.
   */
  private ServiceMetrics settled(PrimeCore core, String name, Predicate<ServiceMetrics> done) {
    ServiceMetrics now = core.metrics().service(name);
    long deadline = System.nanoTime() + patience().toNanos();
    for (int i = 0; i < 10_000_000 && !done.test(now) && System.nanoTime() < deadline; i++) {
      Thread.yield();
      now = core.metrics().service(name);
    }
    assertTrue(done.test(now), "not settled within " + patience() + ": " + now);
    return now;
  }

  private static void assertCounts(
      ServiceMetrics metrics, String kind, long in, long out, long failures) {
    String what = metrics.toString();
    assertEquals(kind, metrics.kind(), what);
    assertEquals(in, metrics.valuesIn(), "in: " + what);
    assertEquals(out, metrics.valuesOut(), "out: " + what);
    assertEquals(failures, metrics.failures(), "failures: " + what);
    assertEquals(in, metrics.processing().count(), "timed: " + what);
    assertTrue(metrics.processing().maxNanos() <= metrics.processing().totalNanos(), what);
  }

  /**
   * An event source counts every publish in and only the publishes the media accepted out: a
   * publish refused with {@code QueueFullException} counts in, not out (architecture,
   * <i>Metrics</i>, "What is metered": event source, in = publishes, out = publishes the media
   * accepted).
   */
  @Test
  default void anEventSourceCountsARefusedPublishInButNotOut() throws Exception {
    int capacity = 2;
    CountDownLatch firstInside = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    List<Throwable> failures = Collections.synchronizedList(new ArrayList<>());
    CoreConfig config =
        CoreConfig.builder()
            .metrics(true)
            .publishTimeout(Duration.ofMillis(200))
            .errorHandler((service, input, error) -> failures.add(error))
            .build();
    try (PrimeCore core = newCoreWithServiceInputCapacity(config, capacity)) {
      EventBlock<Integer> events = new EventBlock<>();
      core.link(core.source("numbers", events), stuckChain(core, "stuck", firstInside, release));
      core.start();
      fillStuckInput(events, firstInside, capacity);
      assertThrows(dev.prime.QueueFullException.class, () -> events.publish(999));
      ServiceMetrics numbers = core.metrics().service("numbers");
      release.countDown();
      assertEquals(capacity + 2, numbers.valuesIn(), "every publish: " + numbers);
      assertEquals(capacity + 1, numbers.valuesOut(), "the accepted publishes only: " + numbers);
      assertEquals(List.of(), failures);
    }
  }

  @Test
  default void aThrowingListenerIsLoggedOncePerBurstAndEveryValueGoesOn() throws Exception {
    int n = 12;
    List<Throwable> failures = Collections.synchronizedList(new ArrayList<>());
    List<String> lines;
    try (CapturedStderr err = new CapturedStderr()) {
      try (PrimeCore core = meteredCore(failures)) {
        EventBlock<Integer> events = new EventBlock<>();
        Reader<Integer> doubled =
            core.source("numbers", events).then(core.chain("noted", (Integer x) -> x * 2)).reader();
        core.metrics()
            .onProcessed(
                "noted",
                (nanos, failed) -> {
                  throw new IllegalStateException("listener broken");
                });
        core.start();
        for (int i = 1; i <= n; i++) {
          events.publish(i);
        }
        List<Integer> out = takeOrFail(doubled, n);
        assertEquals(2 * n, out.get(n - 1), "every value went on past the listener: " + out);
        assertCounts(core.metrics().service("noted"), "BlockChain", n, n, 0);
      } // the count still owed for the burst is written when the core closes
      lines = err.lines();
    }
    assertEquals(List.of(), failures, "a listener's failure is not the service's");
    List<String> mentions =
        lines.stream().filter(l -> l.contains("a metrics listener of 'noted' threw")).toList();
    long full = mentions.stream().filter(l -> l.contains("the value goes on")).count();
    long counted = mentions.stream().mapToLong(CapturedStderr::summarised).sum();
    assertEquals(1, full, "the first failure of the burst in full, once:\n" + String.join("\n", mentions));
    assertEquals(
        n, full + counted, "the lines count every failure:\n" + String.join("\n", mentions));
  }

  /**
   * {@link dev.prime.ProcessingListener}: "what it throws is caught and logged, and the value goes
   * on": also an {@link AssertionError} and a checked exception (a Kotlin listener throws {@code
   * IOException} without declaring it), not only a {@code RuntimeException}.
   */
  @Test
  default void aListenerThrowingAnErrorOrACheckedExceptionIsCaughtAndTheValueGoesOn()
      throws Exception {
    List<Throwable> failures = Collections.synchronizedList(new ArrayList<>());
    try (PrimeCore core = meteredCore(failures)) {
      Block<Integer, Integer> noted = core.chain("noted", (Integer x) -> x * 2).toBlock();
      AtomicLong calls = new AtomicLong();
      core.metrics()
          .onProcessed(
              "noted",
              (nanos, failed) -> {
                if (calls.incrementAndGet() % 2 == 1) {
                  throw new AssertionError("listener broken");
                }
                throw MetricsConformance.<RuntimeException>sneaky(
                    new java.io.IOException("listener cannot write"));
              });
      core.start();
      List<Integer> out = new ArrayList<>();
      for (int i = 1; i <= 4; i++) {
        out.add(noted.process(i));
      }
      assertEquals(List.of(2, 4, 6, 8), out, "every value went on past the listener");
      assertEquals(4, calls.get(), "the listener was told of every value");
      assertCounts(core.metrics().service("noted"), "BlockChain", 4, 4, 0);
    }
    assertEquals(List.of(), failures, "a listener's failure is not the service's");
  }

  /** Throws any throwable, checked or not, without declaring it. */
  @SuppressWarnings("unchecked")
  private static <E extends Throwable> RuntimeException sneaky(Throwable t) throws E {
    throw (E) t;
  }

  /**
   * {@link dev.prime.ProcessingListener}: "Called on the thread that processed the value, right
   * after it (before a chain's output goes on)". The block leaves the value it processed in a
   * thread-local; the listener, told on the same thread right after, finds each value there, in
   * order; and by the time the reader has the output of the i-th value, the listener was told of
   * it.
   */
  @Test
  default void aProcessingListenerIsToldOnTheProcessingThreadBeforeTheOutputGoesOn()
      throws Exception {
    int n = 20;
    List<Throwable> failures = Collections.synchronizedList(new ArrayList<>());
    ThreadLocal<Integer> processedHere = new ThreadLocal<>();
    List<Integer> told = Collections.synchronizedList(new ArrayList<>());
    try (PrimeCore core = meteredCore(failures)) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> doubled =
          core.source("numbers", events)
              .then(
                  core.chain(
                      "noted",
                      (Integer x) -> {
                        processedHere.set(x);
                        return x * 2;
                      }))
              .reader();
      core.metrics()
          .onProcessed(
              "noted",
              (nanos, failed) -> {
                told.add(processedHere.get());
                processedHere.remove();
              });
      core.start();
      for (int i = 1; i <= n; i++) {
        events.publish(i);
      }
      for (int i = 1; i <= n; i++) {
        assertEquals(2 * i, takeOrFail(doubled));
        int toldNow = told.size();
        assertTrue(toldNow >= i, "output " + i + " went on before the listener was told: " + told);
      }
      List<Integer> expected = new ArrayList<>();
      for (int i = 1; i <= n; i++) {
        expected.add(i);
      }
      assertEquals(expected, told, "told on the thread that processed each value, right after it");
    }
    assertEquals(List.of(), failures);
  }
}

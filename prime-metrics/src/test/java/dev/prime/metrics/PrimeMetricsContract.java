package dev.prime.metrics;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Source;
import io.micrometer.core.instrument.Counter;
import io.micrometer.core.instrument.Gauge;
import io.micrometer.core.instrument.Meter;
import io.micrometer.core.instrument.Tag;
import io.micrometer.core.instrument.Timer;
import io.micrometer.core.instrument.config.MeterFilter;
import io.micrometer.core.instrument.distribution.DistributionStatisticConfig;
import io.micrometer.core.instrument.distribution.pause.PauseDetector;
import io.micrometer.core.instrument.simple.SimpleMeterRegistry;
import java.lang.ref.WeakReference;
import java.time.Duration;
import java.util.ArrayList;
import java.util.Collections;
import java.util.HashSet;
import java.util.List;
import java.util.Map;
import java.util.Optional;
import java.util.Set;
import java.util.TreeMap;
import java.util.TreeSet;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;

/** The binder's meters against a real registry, on the media a subclass creates cores of. */
abstract class PrimeMetricsContract {
  static final Duration PATIENCE = Duration.ofSeconds(20);

  /** A new, not started core of the media under test. */
  abstract PrimeCore newCore(CoreConfig config);

  /** The media's short name, as the {@code media} tag gives it. */
  abstract String media();

  /** Whether a value on which a service threw becomes a dead letter. */
  abstract boolean deadLetters();

  /** Whether a chain linked to a source has a queue of its own (an Optimus service). */
  abstract boolean chainsHaveQueues();

  @Test
  void countersAndTheTimerCountEveryValueExactly() throws Exception {
    int n = 50;
    List<Throwable> failures = Collections.synchronizedList(new ArrayList<>());
    CoreConfig config =
        CoreConfig.builder()
            .name("metered")
            .metrics(true)
            .errorHandler((service, input, error) -> failures.add(error))
            .build();
    try (PrimeCore core = newCore(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> numbers = core.source("numbers", events);
      Reader<Integer> doubled = numbers.then(core.chain("double", (Integer x) -> x * 2)).reader();
      Reader<Integer> evens =
          numbers
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
      Block<String, Integer> length = core.chain("length", String::length).toBlock();
      SimpleMeterRegistry registry = new SimpleMeterRegistry();
      try (PrimeMetrics binder = PrimeMetrics.of(core, Duration.ZERO)) {
        binder.bindTo(registry);
        core.start();
        for (int i = 1; i <= n; i++) {
          events.publish(i);
        }
        for (int i = 1; i <= n; i++) {
          assertEquals(2 * i, take(doubled));
        }
        for (int i = 2; i <= n; i += 2) {
          assertEquals(i, take(evens));
        }
        assertEquals(3, length.process("abc"));

        assertEquals(n, count(registry, PrimeMetrics.VALUES_IN, "numbers"));
        assertEquals(n, count(registry, PrimeMetrics.VALUES_OUT, "numbers"));
        assertEquals(n, count(registry, PrimeMetrics.VALUES_IN, "double"));
        assertEquals(n, count(registry, PrimeMetrics.VALUES_OUT, "double"));
        assertEquals(0, count(registry, PrimeMetrics.FAILURES, "double"));
        assertEquals(n, count(registry, PrimeMetrics.VALUES_IN, "picky"));
        assertEquals(n / 2, count(registry, PrimeMetrics.VALUES_OUT, "picky"));
        assertEquals(n / 2, count(registry, PrimeMetrics.FAILURES, "picky"));
        assertEquals(1, count(registry, PrimeMetrics.VALUES_IN, "length"));
        assertEquals(0, count(registry, PrimeMetrics.MISSED, "double"));
        assertEquals(
            deadLetters() ? n / 2 : 0,
            registry.get(PrimeMetrics.DEAD_LETTERS).tag("service", "picky").gauge().value());

        Timer timer = registry.get(PrimeMetrics.PROCESSING).tag("service", "double").timer();
        assertEquals(n, timer.count(), "the timer counts every processed value");
        assertEquals(n, registry.get(PrimeMetrics.PROCESSING).tag("service", "picky").timer().count());
        assertEquals(
            core.metrics().service("double").processing().totalNanos(),
            (long) timer.totalTime(TimeUnit.NANOSECONDS));
        assertEquals(
            core.metrics().service("double").processing().maxNanos(),
            (long) timer.max(TimeUnit.NANOSECONDS));

        Meter.Id id = registry.get(PrimeMetrics.VALUES_IN).tag("service", "double").meter().getId();
        assertEquals("BlockChain", id.getTag("kind"));
        assertEquals(media(), id.getTag("media"));
        assertEquals("metered", id.getTag("core"));
        assertEquals(
            "EventSource",
            registry.get(PrimeMetrics.VALUES_IN).tag("service", "numbers").meter().getId().getTag("kind"));
        assertNull(
            registry.find(PrimeMetrics.QUEUE_DEPTH).tag("service", "numbers").gauge(),
            "a source has no queue");
        Optional<Double> doubleQueue =
            Optional.ofNullable(registry.find(PrimeMetrics.QUEUE_DEPTH).tag("service", "double").gauge())
                .map(g -> g.value());
        assertEquals(chainsHaveQueues() ? Optional.of(0.0) : Optional.empty(), doubleQueue);
        assertEquals(n / 2, failures.size());
      }
      assertEquals(List.of(), registry.getMeters(), "closing the binder removes its meters");
    }
  }

  @Test
  void aFilterHasAQueueDepthGauge() throws Exception {
    try (PrimeCore core = newCore(CoreConfig.builder().metrics(true).build())) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> small = core.source("numbers", events).filter(x -> x < 3).reader();
      SimpleMeterRegistry registry = new SimpleMeterRegistry();
      PrimeMetrics.of(core, Duration.ZERO).bindTo(registry);
      core.start();
      for (int i = 1; i <= 3; i++) {
        events.publish(i);
      }
      assertEquals(1, take(small));
      assertEquals(2, take(small));
      assertNotNull(registry.find(PrimeMetrics.QUEUE_DEPTH).tag("service", "filter(numbers)").gauge());
      assertEquals(
          "Filter",
          registry.get(PrimeMetrics.VALUES_IN).tag("service", "filter(numbers)").meter().getId().getTag("kind"));
      // the third value was tested once its queue is empty and the counts say so
      long deadline = System.nanoTime() + PATIENCE.toNanos();
      double in = 0;
      for (int i = 0; i < 100_000 && in < 3 && System.nanoTime() < deadline; i++) {
        Thread.onSpinWait();
        in = count(registry, PrimeMetrics.VALUES_IN, "filter(numbers)");
      }
      assertEquals(3, in);
      assertEquals(2, count(registry, PrimeMetrics.VALUES_OUT, "filter(numbers)"));
    }
  }

  @Test
  void aSnapshotServesTheReadsOfItsRefreshPeriod() throws Exception {
    try (PrimeCore core = newCore(CoreConfig.builder().metrics(true).build())) {
      Block<Integer, Integer> same = core.chain("same", (Integer x) -> x).toBlock();
      SimpleMeterRegistry cached = new SimpleMeterRegistry();
      SimpleMeterRegistry exact = new SimpleMeterRegistry();
      PrimeMetrics.of(core, Duration.ofHours(1)).bindTo(cached);
      PrimeMetrics.of(core, Duration.ZERO).bindTo(exact);
      core.start();
      assertEquals(0, count(cached, PrimeMetrics.VALUES_IN, "same")); // the snapshot is taken
      assertEquals(7, same.process(7));
      assertEquals(0, count(cached, PrimeMetrics.VALUES_IN, "same"), "served from the snapshot");
      assertEquals(1, count(exact, PrimeMetrics.VALUES_IN, "same"));
      assertEquals(1, cached.get(PrimeMetrics.PROCESSING).tag("service", "same").timer().count(),
          "the timer is told of each value, not read from snapshots");
    }
  }

  /**
   * {@link PrimeMetrics#of(PrimeCore, Duration)} refuses only a negative refresh: one as long as a
   * {@link Duration} holds is a snapshot that serves every read.
   */
  @Test
  void aRefreshAsLongAsADurationHoldsServesTheFirstSnapshot() throws Exception {
    try (PrimeCore core = newCore(CoreConfig.builder().metrics(true).build())) {
      Block<Integer, Integer> same = core.chain("same", (Integer x) -> x).toBlock();
      SimpleMeterRegistry registry = new SimpleMeterRegistry();
      try (PrimeMetrics binder = PrimeMetrics.of(core, Duration.ofSeconds(Long.MAX_VALUE))) {
        binder.bindTo(registry);
        core.start();
        assertEquals(0, count(registry, PrimeMetrics.VALUES_IN, "same")); // the snapshot is taken
        assertEquals(7, same.process(7));
        assertEquals(0, count(registry, PrimeMetrics.VALUES_IN, "same"), "served from the snapshot");
        assertEquals(1, registry.get(PrimeMetrics.PROCESSING).tag("service", "same").timer().count());
      }
    }
  }

  @Test
  void metricsOffAreRefusedWithHowToTurnThemOn() {
    try (PrimeCore core = newCore(CoreConfig.defaults())) {
      IllegalStateException e = assertThrows(IllegalStateException.class, () -> PrimeMetrics.of(core));
      assertTrue(e.getMessage().contains("CoreConfig.builder().metrics(true)"), e.getMessage());
    }
  }

  @Test
  void aNegativeRefreshIsRefusedWithItsValue() {
    try (PrimeCore core = newCore(CoreConfig.builder().metrics(true).build())) {
      IllegalArgumentException e =
          assertThrows(IllegalArgumentException.class, () -> PrimeMetrics.of(core, Duration.ofMillis(-5)));
      assertTrue(e.getMessage().contains("PT-0.005S"), e.getMessage());
    }
  }

  @Test
  void oneBinderServesTwoRegistriesUntilItClosesThenTimesNothing() throws Exception {
    try (PrimeCore core = newCore(CoreConfig.builder().metrics(true).build())) {
      Block<Integer, Integer> same = core.chain("same", (Integer x) -> x).toBlock();
      SimpleMeterRegistry first = new SimpleMeterRegistry();
      SimpleMeterRegistry second = new SimpleMeterRegistry();
      PrimeMetrics binder = PrimeMetrics.of(core, Duration.ZERO);
      binder.bindTo(first);
      binder.bindTo(second);
      Block<Integer, Integer> late = core.chain("late", (Integer x) -> x + 1).toBlock();
      core.start();
      assertEquals(7, same.process(7));
      assertEquals(2, late.process(1));
      Timer firstTimer = first.get(PrimeMetrics.PROCESSING).tag("service", "same").timer();
      Timer secondTimer = second.get(PrimeMetrics.PROCESSING).tag("service", "same").timer();
      assertEquals(1, count(first, PrimeMetrics.VALUES_IN, "same"));
      assertEquals(1, count(second, PrimeMetrics.VALUES_IN, "same"));
      assertEquals(1, firstTimer.count());
      assertEquals(1, secondTimer.count());
      assertEquals(
          List.of(),
          first.find(PrimeMetrics.VALUES_IN).tag("service", "late").meters(),
          "a node declared after binding gets no meters");

      binder.close();
      binder.close(); // twice does nothing
      assertEquals(List.of(), first.getMeters(), "closing removes the meters of every registry");
      assertEquals(List.of(), second.getMeters(), "closing removes the meters of every registry");
      assertEquals(8, same.process(8));
      assertEquals(1, firstTimer.count(), "a closed binder times no more values");
      assertEquals(1, secondTimer.count(), "a closed binder times no more values");
    }
  }

  /**
   * The missed counter is the event source's {@code missed()}: what a reader that fell behind the
   * source's retention lost.
   */
  @Test
  void theMissedCounterCountsWhatALaggingReaderLost() throws Exception {
    int retention = 4;
    int published = 20;
    CoreConfig config = CoreConfig.builder().metrics(true).sourceRetention(retention).build();
    try (PrimeCore core = newCore(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> lagging = core.source("numbers", events).reader();
      SimpleMeterRegistry registry = new SimpleMeterRegistry();
      PrimeMetrics.of(core, Duration.ZERO).bindTo(registry);
      core.start();
      for (int i = 1; i <= published; i++) {
        events.publish(i);
      }
      assertEquals(published - retention + 1, take(lagging), "the oldest value retained");
      long missed = lagging.missed();
      assertTrue(missed > 0, "the reader missed values: " + missed);
      assertEquals(missed, core.metrics().service("numbers").missed());
      assertEquals(missed, count(registry, PrimeMetrics.MISSED, "numbers"));
      assertEquals(published, count(registry, PrimeMetrics.VALUES_IN, "numbers"));
    }
  }

  /**
   * The queue-depth gauge is the node's {@code queueDepth()}: the values waiting in its input and
   * the one in progress.
   */
  @Test
  void theQueueDepthGaugeCountsWhatWaitsAndWhatIsInProgress() throws Exception {
    CountDownLatch started = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    try (PrimeCore core = newCore(CoreConfig.builder().metrics(true).build())) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> passed =
          core.source("numbers", events)
              .filter(
                  x -> {
                    started.countDown();
                    try {
                      return release.await(PATIENCE.toMillis(), TimeUnit.MILLISECONDS);
                    } catch (InterruptedException e) {
                      Thread.currentThread().interrupt();
                      return false;
                    }
                  })
              .reader();
      SimpleMeterRegistry registry = new SimpleMeterRegistry();
      PrimeMetrics.of(core, Duration.ZERO).bindTo(registry);
      core.start();
      for (int i = 1; i <= 3; i++) {
        events.publish(i);
      }
      try {
        assertTrue(started.await(PATIENCE.toMillis(), TimeUnit.MILLISECONDS), "the filter never ran");
        Gauge depth = registry.get(PrimeMetrics.QUEUE_DEPTH).tag("service", "filter(numbers)").gauge();
        long deadline = System.nanoTime() + PATIENCE.toNanos();
        double seen = depth.value();
        for (int i = 0; i < 100_000 && seen != 3 && System.nanoTime() < deadline; i++) {
          Thread.onSpinWait();
          seen = depth.value();
        }
        assertEquals(3, seen, "one value in progress and two waiting");
        assertEquals(core.metrics().service("filter(numbers)").queueDepth(), (long) depth.value());
      } finally {
        release.countDown();
      }
      for (int i = 1; i <= 3; i++) {
        assertEquals(i, take(passed));
      }
    }
  }

  /**
   * Bound after the core started, the counters count every value the core counted, and the timer
   * every value processed after binding.
   */
  @Test
  void aBinderBoundAfterTheStartCountsEverythingAndTimesWhatFollows() throws Exception {
    try (PrimeCore core = newCore(CoreConfig.builder().metrics(true).build())) {
      Block<Integer, Integer> same = core.chain("same", (Integer x) -> x).toBlock();
      core.start();
      assertEquals(1, same.process(1));
      SimpleMeterRegistry registry = new SimpleMeterRegistry();
      PrimeMetrics.of(core, Duration.ZERO).bindTo(registry);
      assertEquals(2, same.process(2));
      assertEquals(2, count(registry, PrimeMetrics.VALUES_IN, "same"));
      assertEquals(2, count(registry, PrimeMetrics.VALUES_OUT, "same"));
      assertEquals(1, registry.get(PrimeMetrics.PROCESSING).tag("service", "same").timer().count());
    }
  }

  /**
   * Nodes declared after the binding get no meters (bind once the diagram is declared), before
   * the start and after it, and do not disturb the meters of those declared before.
   */
  @Test
  void nodesDeclaredAfterTheBindingGetNoMeters() throws Exception {
    try (PrimeCore core = newCore(CoreConfig.builder().metrics(true).build())) {
      Block<Integer, Integer> early = core.chain("early", (Integer x) -> x).toBlock();
      SimpleMeterRegistry registry = new SimpleMeterRegistry();
      PrimeMetrics binder = PrimeMetrics.of(core, Duration.ZERO);
      binder.bindTo(registry);
      List<Meter> meters = List.copyOf(registry.getMeters());
      Block<Integer, Integer> beforeStart = core.chain("before-start", (Integer x) -> x + 1).toBlock();
      core.start();
      Block<Integer, Integer> afterStart = core.chain("after-start", (Integer x) -> x + 2).toBlock();
      assertEquals(1, early.process(1));
      assertEquals(2, beforeStart.process(1));
      assertEquals(3, afterStart.process(1));
      assertEquals(1, count(registry, PrimeMetrics.VALUES_IN, "early"));
      assertEquals(meters, registry.getMeters(), "the nodes declared after the binding got meters");
      binder.close();
    }
  }

  /**
   * The timer asks for a percentile histogram, so a registry that publishes aggregable
   * percentiles (Prometheus, ...) gets its buckets.
   */
  @Test
  void theTimerAsksForAPercentileHistogram() {
    try (PrimeCore core = newCore(CoreConfig.builder().metrics(true).build())) {
      core.chain("same", (Integer x) -> x);
      List<DistributionStatisticConfig> timers = new ArrayList<>();
      SimpleMeterRegistry registry =
          new SimpleMeterRegistry() {
            @Override
            protected Timer newTimer(
                Meter.Id id, DistributionStatisticConfig config, PauseDetector pauseDetector) {
              timers.add(config);
              return super.newTimer(id, config, pauseDetector);
            }
          };
      PrimeMetrics.of(core, Duration.ZERO).bindTo(registry);
      assertEquals(1, timers.size());
      assertEquals(Boolean.TRUE, timers.get(0).isPercentileHistogram(), "the timer's histogram");
    }
  }

  /**
   * A binder the program keeps no reference to, as in {@code PrimeMetrics.of(core).bindTo(registry)},
   * keeps its meters reading the core's metrics after a garbage collection.
   */
  @Test
  void theMetersOfABinderNobodyKeepsGoOnReadingAfterAGarbageCollection() throws Exception {
    try (PrimeCore core = newCore(CoreConfig.builder().metrics(true).build())) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> small = core.source("numbers", events).filter(x -> x < 100).reader();
      SimpleMeterRegistry registry = new SimpleMeterRegistry();
      PrimeMetrics.of(core, Duration.ZERO).bindTo(registry); // nothing keeps the binder
      core.start();
      assertEquals(0, count(registry, PrimeMetrics.VALUES_IN, "numbers"));
      collectGarbage();
      events.publish(1);
      assertEquals(1, take(small));
      assertEquals(1, count(registry, PrimeMetrics.VALUES_IN, "numbers"), "the counter after a GC");
      assertEquals(
          0.0,
          registry.get(PrimeMetrics.QUEUE_DEPTH).tag("service", "filter(numbers)").gauge().value(),
          "the gauge after a GC");
    }
  }

  /** Runs the collector until an object nothing refers to is gone (at most 50 times). */
  private static void collectGarbage() {
    WeakReference<Object> canary = new WeakReference<>(new Object());
    for (int i = 0; i < 50 && canary.get() != null; i++) {
      System.gc();
    }
    assertNull(canary.get(), "no garbage collection happened");
  }

  /**
   * Binding again to a registry the binder is bound to changes nothing: the registry holds one
   * meter of each name and tags, and its timer counts each value once.
   */
  @Test
  void bindingTwiceToOneRegistryTimesEachValueOnce() throws Exception {
    try (PrimeCore core = newCore(CoreConfig.builder().metrics(true).build())) {
      Block<Integer, Integer> same = core.chain("same", (Integer x) -> x).toBlock();
      SimpleMeterRegistry registry = new SimpleMeterRegistry();
      PrimeMetrics binder = PrimeMetrics.of(core, Duration.ZERO);
      binder.bindTo(registry);
      int meters = registry.getMeters().size();
      binder.bindTo(registry);
      core.start();
      assertEquals(7, same.process(7));
      assertEquals(meters, registry.getMeters().size());
      assertEquals(1, registry.get(PrimeMetrics.PROCESSING).tag("service", "same").timer().count());
      binder.close();
      assertEquals(List.of(), registry.getMeters());
    }
  }

  /**
   * A second binder of one core on one registry is refused with a message that names the node and
   * the fix, registers nothing, and leaves the first binder's meters counting and timing each
   * value once; once the first is closed, the second binds.
   */
  @Test
  void aSecondBinderOfACoreOnOneRegistryIsRefusedAndChangesNothing() throws Exception {
    try (PrimeCore core = newCore(CoreConfig.builder().name("twice").metrics(true).build())) {
      Block<Integer, Integer> same = core.chain("same", (Integer x) -> x).toBlock();
      SimpleMeterRegistry registry = new SimpleMeterRegistry();
      PrimeMetrics first = PrimeMetrics.of(core, Duration.ZERO);
      first.bindTo(registry);
      List<Meter> meters = List.copyOf(registry.getMeters());
      PrimeMetrics second = PrimeMetrics.of(core, Duration.ZERO);
      IllegalStateException refused =
          assertThrows(IllegalStateException.class, () -> second.bindTo(registry));
      assertTrue(refused.getMessage().contains("node 'same' of core 'twice'")
              && refused.getMessage().contains("one PrimeMetrics per core and registry"),
          refused.getMessage());
      core.start();
      assertEquals(7, same.process(7));
      second.close();
      assertEquals(meters, registry.getMeters(), "the refused binder registered and removed nothing");
      assertEquals(1, registry.get(PrimeMetrics.PROCESSING).tag("service", "same").timer().count(),
          "each value timed once");
      assertEquals(1.0, registry.get(PrimeMetrics.VALUES_IN).tag("service", "same").functionCounter().count());

      first.close();
      second.bindTo(registry);
      assertEquals(meters.size(), registry.getMeters().size(), "the second binds once the first is closed");
      second.close();
    }
  }

  /**
   * A second core whose name, media and nodes are those of a core bound to a registry would share
   * its meters: its binder is refused there with the fix, registers nothing and times nothing; a
   * core of another name binds beside the first, and the second binds once the first binder is
   * closed.
   */
  @Test
  void aCoreWithTheNameMediaAndNodesOfACoreBoundThereIsRefused() throws Exception {
    try (PrimeCore first = newCore(CoreConfig.builder().name("twin").metrics(true).build());
        PrimeCore second = newCore(CoreConfig.builder().name("twin").metrics(true).build());
        PrimeCore other = newCore(CoreConfig.builder().name("other").metrics(true).build())) {
      Block<Integer, Integer> firstSame = first.chain("same", (Integer x) -> x).toBlock();
      Block<Integer, Integer> secondSame = second.chain("same", (Integer x) -> x).toBlock();
      other.chain("same", (Integer x) -> x);
      SimpleMeterRegistry registry = new SimpleMeterRegistry();
      PrimeMetrics firstBinder = PrimeMetrics.of(first, Duration.ZERO);
      firstBinder.bindTo(registry);
      List<Meter> meters = List.copyOf(registry.getMeters());
      PrimeMetrics secondBinder = PrimeMetrics.of(second, Duration.ZERO);
      IllegalStateException refused =
          assertThrows(IllegalStateException.class, () -> secondBinder.bindTo(registry),
              "a binder of another core named 'twin' on the registry");
      assertTrue(refused.getMessage().contains("node 'same' of core 'twin'")
              && refused.getMessage().contains("give cores bound to one registry distinct names"),
          refused.getMessage());
      assertEquals(meters, registry.getMeters(), "the refused binder registered nothing");
      first.start();
      second.start();
      assertEquals(2, secondSame.process(2));
      Timer timer = registry.get(PrimeMetrics.PROCESSING).tags("service", "same", "core", "twin").timer();
      assertEquals(0, timer.count(), "the refused binder times nothing");
      assertEquals(1, firstSame.process(1));
      assertEquals(1, timer.count(), "the first core's value, timed once");

      PrimeMetrics otherBinder = PrimeMetrics.of(other, Duration.ZERO);
      otherBinder.bindTo(registry);
      assertEquals(2 * meters.size(), registry.getMeters().size(), "a core of another name binds beside it");
      otherBinder.close();

      firstBinder.close();
      secondBinder.bindTo(registry);
      assertEquals(meters.size(), registry.getMeters().size(), "the second binds once the first is closed");
      secondBinder.close();
    }
  }

  /**
   * A registry that refuses one of a node's meters (it holds a meter of another type under that
   * name and tags) fails the binding with a message that names the node and the fix, and keeps
   * nothing of it: no meter of the nodes bound before, no timer timing values; once the meter in
   * the way is gone, the binder binds and times each value once.
   */
  @Test
  void aBindingTheRegistryRefusesHalfWayKeepsNothingAndSaysWhy() throws Exception {
    try (PrimeCore core = newCore(CoreConfig.builder().name("refused").metrics(true).build())) {
      Block<Integer, Integer> first = core.chain("first", (Integer x) -> x).toBlock();
      core.chain("second", (Integer x) -> x);
      SimpleMeterRegistry registry = new SimpleMeterRegistry();
      Counter inTheWay =
          Counter.builder(PrimeMetrics.PROCESSING)
              .tags("service", "second", "kind", "BlockChain", "media", media(), "core", "refused")
              .register(registry);
      PrimeMetrics binder = PrimeMetrics.of(core, Duration.ZERO);
      IllegalStateException refused =
          assertThrows(IllegalStateException.class, () -> binder.bindTo(registry));
      assertTrue(refused.getMessage().contains("node 'second' of core 'refused'")
              && refused.getMessage().contains("remove the meter in the way"),
          refused.getMessage());
      assertEquals(List.of(inTheWay), registry.getMeters(), "the refused binding left meters");
      core.start();
      assertEquals(1, first.process(1));

      registry.remove(inTheWay);
      binder.bindTo(registry);
      assertEquals(2, first.process(2));
      assertEquals(1, registry.get(PrimeMetrics.PROCESSING).tag("service", "first").timer().count(),
          "the value after the binding, timed once");
      binder.close();
      assertEquals(List.of(), registry.getMeters(), "closing the binder removes its meters");
    }
  }

  /**
   * A registry's meter filter may rename the meters (a prefix, say): a second binder of a core is
   * refused there too, and changes nothing, rather than sharing the first one's meters and timing
   * each value twice.
   */
  @Test
  void aSecondBinderIsRefusedAlsoWhereAMeterFilterRenamesTheMeters() throws Exception {
    try (PrimeCore core = newCore(CoreConfig.builder().name("renamed").metrics(true).build())) {
      Block<Integer, Integer> same = core.chain("same", (Integer x) -> x).toBlock();
      SimpleMeterRegistry registry = new SimpleMeterRegistry();
      registry.config().meterFilter(new MeterFilter() {
        @Override
        public Meter.Id map(Meter.Id id) {
          return id.withName("robot." + id.getName());
        }
      });
      PrimeMetrics first = PrimeMetrics.of(core, Duration.ZERO);
      first.bindTo(registry);
      List<Meter> meters = List.copyOf(registry.getMeters());
      PrimeMetrics second = PrimeMetrics.of(core, Duration.ZERO);
      IllegalStateException refused =
          assertThrows(IllegalStateException.class, () -> second.bindTo(registry),
              "a second binder of the core on the registry");
      assertTrue(refused.getMessage().contains("node 'same' of core 'renamed'")
              && refused.getMessage().contains("one PrimeMetrics per core and registry"),
          refused.getMessage());
      assertEquals(meters, registry.getMeters(), "the refused binder registered nothing");
      core.start();
      assertEquals(7, same.process(7));
      second.close();
      assertEquals(meters, registry.getMeters(), "the refused binder removed nothing");
      assertEquals(1,
          registry.get("robot." + PrimeMetrics.PROCESSING).tag("service", "same").timer().count(),
          "each value timed once");
      first.close();
      assertEquals(List.of(), registry.getMeters(), "closing the binder removes its meters");
    }
  }

  /**
   * The meters are named and tagged as the README and the Javadoc say, for every kind of metered
   * node: chains, filters, flat-maps, listeners, event sources, combinators, timers and generic
   * services.
   */
  @Test
  void everyMeteredNodeGetsTheMetersTheDocsName() {
    try (PrimeCore core = newCore(CoreConfig.builder().name("named").metrics(true).build())) {
      Source<Integer> numbers = core.source("numbers", new EventBlock<Integer>());
      Source<Integer> others = core.source("others", new EventBlock<Integer>());
      core.chain("same", (Integer x) -> x);
      numbers.filter(x -> x > 0);
      numbers.flatMap(x -> List.of(x, x));
      numbers.listen(x -> {});
      core.merge(numbers, others);
      core.timer("clock", Duration.ofHours(1));
      core.service("idle", () -> {});
      SimpleMeterRegistry registry = new SimpleMeterRegistry();
      PrimeMetrics.of(core).bindTo(registry);

      Set<String> names = new TreeSet<>();
      Set<List<String>> tagKeys = new HashSet<>();
      Map<String, String> kinds = new TreeMap<>();
      for (Meter meter : registry.getMeters()) {
        names.add(meter.getId().getName());
        tagKeys.add(meter.getId().getTags().stream().map(Tag::getKey).sorted().toList());
        assertEquals(media(), meter.getId().getTag("media"));
        assertEquals("named", meter.getId().getTag("core"));
        kinds.put(meter.getId().getTag("service"), meter.getId().getTag("kind"));
      }
      assertEquals(
          new TreeSet<>(
              List.of(
                  "prime.service.values.in",
                  "prime.service.values.out",
                  "prime.service.failures",
                  "prime.service.missed",
                  "prime.service.dead.letters",
                  "prime.service.queue.depth",
                  "prime.service.processing")),
          names);
      assertEquals(Set.of(List.of("core", "kind", "media", "service")), tagKeys);
      assertEquals("BlockChain", kinds.get("same"));
      assertEquals("Filter", kinds.get("filter(numbers)"));
      assertEquals("FlatMap", kinds.get("flatMap(numbers)"));
      assertEquals("Listener", kinds.get("listen(numbers)"));
      assertEquals("EventSource", kinds.get("numbers"));
      assertEquals("Combinator", kinds.get("merge(numbers|others)"));
      assertEquals("Timer", kinds.get("clock"));
      assertEquals("GenericServiceNode", kinds.get("idle"));
      for (String service : kinds.keySet()) {
        long meters =
            registry.getMeters().stream()
                .filter(m -> service.equals(m.getId().getTag("service")))
                .count();
        boolean queue = registry.find(PrimeMetrics.QUEUE_DEPTH).tag("service", service).gauge() != null;
        assertEquals(queue ? 7 : 6, meters, "the meters of " + service);
      }
    }
  }

  static double count(SimpleMeterRegistry registry, String meter, String service) {
    return registry.get(meter).tag("service", service).functionCounter().count();
  }

  static <T> T take(Reader<T> reader) throws InterruptedException {
    return reader.take(PATIENCE).orElseThrow(() -> new AssertionError("nothing within " + PATIENCE));
  }
}

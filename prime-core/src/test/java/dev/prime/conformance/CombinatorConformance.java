package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.CoreClosedException;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeClock;
import dev.prime.PrimeCore;
import dev.prime.QueueFullException;
import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.Tick;
import dev.prime.Tuple2;
import dev.prime.Tuple3;
import dev.prime.Tuple5;
import dev.prime.VirtualClock;
import dev.prime.topology.Topology;
import dev.prime.topology.TopologyNode;
import java.time.Duration;
import java.time.Instant;
import java.util.ArrayList;
import java.util.List;
import java.util.Optional;
import java.util.concurrent.BlockingQueue;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.LinkedBlockingQueue;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicInteger;
import java.util.concurrent.atomic.AtomicLong;
import org.junit.jupiter.api.Assumptions;
import org.junit.jupiter.api.Test;

/**
 * Combinators of sources (combine-latest, zip, merge, with-latest-from, sample, the conflated
 * reader) and timers on the core's clock: which values pair, in what order, on every media.
 * Where values of several inputs race, a test publishes the next value only after it saw the
 * output of the previous one, so the expected output is exact.
 */
public interface CombinatorConformance extends ConformanceBase {

  /** How long a test waits to see that nothing is published. */
  default Duration quiet() {
    return Duration.ofMillis(300);
  }

  /**
   * A declaration that fails leaves nothing behind and can be made again: on a started core, a
   * merge whose second input's reader cannot be opened fails, runs nothing of it (no service of
   * its first input), and the same merge made again publishes each value once.
   */
  @Test
  default void aMergeThatFailedAfterStartLeavesNothingRunningAndCanBeMadeAgain()
      throws InterruptedException {
    try (PrimeCore core = newCore();
        PrimeCore other = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> numbers = core.source("numbers", events);
      EventBlock<Integer> otherEvents = new EventBlock<>();
      Source<Integer> others = other.source("others", otherEvents);
      AtomicInteger opened = new AtomicInteger();
      Source<Integer> flaky = AtomicLinkConformance.failingFirstReader(others, opened);
      other.start();
      core.start();
      IllegalStateException e =
          assertThrows(IllegalStateException.class, () -> core.merge(numbers, flaky));
      assertEquals("this source cannot be read yet", e.getMessage());
      Reader<Integer> merged = core.merge(numbers, flaky).reader();
      events.publish(1);
      assertEquals(Optional.of(1), merged.take(patience()), "the merge made again runs");
      assertEquals(
          Optional.empty(), merged.take(quiet()), "each value once: nothing of the failed merge runs");
    }
  }

  @Test
  default void combineLatestPairsEachNewValueWithTheLatestOfTheOtherOnceBothHaveOne()
      throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> aEvents = new EventBlock<>();
      EventBlock<String> bEvents = new EventBlock<>();
      Source<Tuple2<Integer, String>> both =
          core.combineLatest(core.source("a", aEvents), core.source("b", bEvents));
      assertEquals("combineLatest(a|b)", both.name());
      Reader<Tuple2<Integer, String>> out = both.reader();
      core.start();
      aEvents.publish(1);
      assertEquals(Optional.empty(), out.take(quiet()), "no output before b has a value");
      bEvents.publish("x");
      assertEquals(new Tuple2<>(1, "x"), takeOrFail(out));
      aEvents.publish(2);
      assertEquals(new Tuple2<>(2, "x"), takeOrFail(out));
      bEvents.publish("y");
      assertEquals(new Tuple2<>(2, "y"), takeOrFail(out));
      bEvents.publish("z");
      assertEquals(new Tuple2<>(2, "z"), takeOrFail(out));
      assertEquals(List.of(), out.drain());
    }
  }

  @Test
  default void combineLatestOfFiveSourcesEmitsFirstWhenTheLastOneHasAValue()
      throws InterruptedException {
    try (PrimeCore core = newCore()) {
      List<EventBlock<Integer>> events = new ArrayList<>();
      List<Source<Integer>> sources = new ArrayList<>();
      for (int i = 0; i < 5; i++) {
        events.add(new EventBlock<>());
        sources.add(core.source("s" + i, events.get(i)));
      }
      Reader<Tuple5<Integer, Integer, Integer, Integer, Integer>> out =
          core.combineLatest(
                  sources.get(0), sources.get(1), sources.get(2), sources.get(3), sources.get(4))
              .reader();
      core.start();
      for (int i = 0; i < 5; i++) {
        events.get(i).publish(10 + i);
      }
      assertEquals(new Tuple5<>(10, 11, 12, 13, 14), takeOrFail(out));
      events.get(2).publish(22);
      assertEquals(new Tuple5<>(10, 11, 22, 13, 14), takeOrFail(out));
      assertEquals(Optional.empty(), out.take(quiet()));
    }
  }

  @Test
  default void zipPairsTheNthValueOfEachSourceWithTheNthOfTheOthers()
      throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> aEvents = new EventBlock<>();
      EventBlock<String> bEvents = new EventBlock<>();
      EventBlock<Boolean> cEvents = new EventBlock<>();
      Source<Tuple3<Integer, String, Boolean>> zipped =
          core.zip(
              core.source("a", aEvents), core.source("b", bEvents), core.source("c", cEvents));
      assertEquals("zip(a|b|c)", zipped.name());
      Reader<Tuple3<Integer, String, Boolean>> out = zipped.reader();
      core.start();
      for (int i = 1; i <= 3; i++) {
        aEvents.publish(i);
      }
      bEvents.publish("one");
      bEvents.publish("two");
      assertEquals(Optional.empty(), out.take(quiet()), "no tuple before c has a value");
      cEvents.publish(true);
      cEvents.publish(false);
      cEvents.publish(true);
      assertEquals(
          List.of(new Tuple3<>(1, "one", true), new Tuple3<>(2, "two", false)),
          takeOrFail(out, 2));
      assertEquals(Optional.empty(), out.take(quiet()), "a's 3rd and c's 3rd wait for b's 3rd");
      bEvents.publish("three");
      assertEquals(new Tuple3<>(3, "three", true), takeOrFail(out));
    }
  }

  @Test
  default void mergeKeepsTheOrderOfEachSourceAndLosesNothing() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> odd = new EventBlock<>();
      EventBlock<Integer> even = new EventBlock<>();
      Source<Number> merged = core.merge(core.source("odd", odd), core.source("even", even));
      assertEquals("merge(odd|even)", merged.name());
      Reader<Number> out = merged.reader();
      core.start();
      for (int i = 0; i < 50; i++) {
        odd.publish(2 * i + 1);
        even.publish(2 * i);
      }
      List<Number> all = takeOrFail(out, 100);
      List<Integer> odds = new ArrayList<>();
      List<Integer> evens = new ArrayList<>();
      for (Number n : all) {
        (n.intValue() % 2 == 1 ? odds : evens).add(n.intValue());
      }
      List<Integer> expectedOdds = new ArrayList<>();
      List<Integer> expectedEvens = new ArrayList<>();
      for (int i = 0; i < 50; i++) {
        expectedOdds.add(2 * i + 1);
        expectedEvens.add(2 * i);
      }
      assertEquals(expectedOdds, odds);
      assertEquals(expectedEvens, evens);
      assertEquals(Optional.empty(), out.take(quiet()));
    }
  }

  /**
   * On the in-memory media each input of a combinator is a queue like a service's: values
   * published before {@code start()} wait in it (none is missed, whatever the source's window),
   * and once it holds {@code sourceRetention()} values a publish waits {@code publishTimeout} and
   * fails with {@link QueueFullException} naming the combinator. (Optimus refuses a publish before
   * the start, and its combinators read through readers of their own.)
   */
  @Test
  default void aCombinatorsInputIsAQueueThatHoldsThePublisherWhenFull() throws Exception {
    Assumptions.assumeTrue(
        publishesBeforeStartWait(), "in-memory media: a publish before the start waits");
    CoreConfig config =
        CoreConfig.builder().sourceRetention(4).publishTimeout(Duration.ofMillis(200)).build();
    try (PrimeCore core = newCore(config)) {
      EventBlock<Integer> odd = new EventBlock<>();
      EventBlock<Integer> even = new EventBlock<>();
      Source<Number> merged = core.merge(core.source("odd", odd), core.source("even", even));
      Reader<Number> out = merged.reader();
      for (int i = 1; i <= 4; i++) {
        odd.publish(2 * i - 1);
      }
      QueueFullException full = assertThrows(QueueFullException.class, () -> odd.publish(9));
      assertEquals("merge(odd|even)", full.serviceName(), full.getMessage());
      assertEquals(4, full.capacity(), full.getMessage());
      core.start();
      assertEquals(List.of(1, 3, 5, 7), takeOrFail(out, 4), "every value the input held");
      assertEquals(Optional.empty(), out.take(quiet()), "the refused value was not published");
    }
  }

  @Test
  default void withLatestFromEnrichesEachValueAndDropsThoseBeforeTheOtherHasOne()
      throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Double> gyroEvents = new EventBlock<>();
      EventBlock<String> lineEvents = new EventBlock<>();
      Source<Double> gyro = core.source("gyro", gyroEvents);
      Source<String> line = core.source("line", lineEvents);
      Source<Tuple2<Double, String>> fused = gyro.withLatestFrom(line);
      assertEquals("withLatestFrom(gyro|line)", fused.name());
      Reader<Tuple2<Double, String>> out = fused.reader();
      core.start();
      gyroEvents.publish(0.1);
      gyroEvents.publish(0.2);
      assertEquals(Optional.empty(), out.take(quiet()), "no line value yet: gyro values dropped");
      lineEvents.publish("left");
      assertEquals(Optional.empty(), out.take(quiet()), "a line value alone emits nothing");
      gyroEvents.publish(0.3);
      assertEquals(new Tuple2<>(0.3, "left"), takeOrFail(out));
      gyroEvents.publish(0.4);
      assertEquals(new Tuple2<>(0.4, "left"), takeOrFail(out));
      lineEvents.publish("right");
      lineEvents.publish("centre");
      assertEquals(Optional.empty(), out.take(quiet()));
      gyroEvents.publish(0.5);
      assertEquals(new Tuple2<>(0.5, "centre"), takeOrFail(out));
    }
  }

  @Test
  default void sampleEmitsTheLatestValueOncePerPeriodAndNothingWithoutANewOne()
      throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> sampled = core.source("fast", events).sample(Duration.ofMillis(100));
      assertEquals("sample(fast)", sampled.name());
      Reader<Integer> out = sampled.reader();
      core.start();
      for (int i = 1; i <= 100; i++) {
        events.publish(i);
      }
      List<Integer> seen = new ArrayList<>();
      long deadline = System.nanoTime() + patience().toNanos();
      while ((seen.isEmpty() || seen.get(seen.size() - 1) != 100) && System.nanoTime() < deadline) {
        out.take(Duration.ofMillis(200)).ifPresent(seen::add);
      }
      assertTrue(!seen.isEmpty() && seen.get(seen.size() - 1) == 100, "the last value: " + seen);
      for (int i = 1; i < seen.size(); i++) {
        assertTrue(seen.get(i - 1) < seen.get(i), "samples go forward: " + seen);
      }
      assertTrue(seen.size() < 100, "a sample per period, not per value: " + seen);
      assertEquals(Optional.empty(), out.take(Duration.ofMillis(350)), "no new value, no sample");
      events.publish(101);
      assertEquals(101, takeOrFail(out));
    }
  }

  @Test
  default void sampleTicksOnTheCoresClock() throws InterruptedException {
    VirtualClock clock = new VirtualClock();
    try (PrimeCore core = newCore(CoreConfig.builder().clock(clock).build())) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> out = core.source("fast", events).sample(Duration.ofSeconds(1)).reader();
      core.start();
      events.publish(1);
      events.publish(2);
      assertEquals(Optional.empty(), out.take(quiet()), "virtual time stands still: no sample");
      Optional<Integer> sample = Optional.empty();
      for (int second = 0; second < 100 && !sample.equals(Optional.of(2)); second++) {
        clock.advance(Duration.ofSeconds(1));
        sample = out.take(Duration.ofMillis(200));
        assertTrue(sample.isEmpty() || sample.get() <= 2, "only published values: " + sample);
      }
      assertEquals(Optional.of(2), sample, "the latest value, once the clock moved");
    }
  }

  /**
   * {@link Source#sample}: "Periods count from the core's start (from this call, on a started
   * core, as a timer's do)". A sampler declared on a started core, 3.5 periods after the start by a
   * {@link VirtualClock}, publishes nothing for the periods before its declaration: a value it took
   * is published when one period has passed since the declaration, not at the start's fourth
   * period.
   */
  @Test
  default void aSamplerDeclaredOnAStartedCoreCountsItsPeriodsFromItsDeclaration()
      throws InterruptedException {
    VirtualClock clock = new VirtualClock();
    CoreConfig config = CoreConfig.builder().clock(clock).metrics(true).build();
    try (PrimeCore core = newCore(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> values = core.source("values", events);
      core.start();
      clock.advance(Duration.ofMillis(3_500));
      Reader<Integer> sampled = values.sample(Duration.ofSeconds(1)).reader();
      events.publish(7);
      awaitValuesIn(core, "sample(values)", 1); // the sampler took 7
      clock.advance(Duration.ofMillis(999)); // past the start's fourth period, not one since
      assertEquals(Optional.empty(), sampled.take(quiet()), "no period ended since the declaration");
      clock.advance(Duration.ofMillis(1));
      assertEquals(7, takeOrFail(sampled), "one period after the declaration");
    }
  }

  @Test
  default void timerTicksExactlyOnAVirtualClock() throws InterruptedException {
    VirtualClock clock = new VirtualClock();
    Instant origin = clock.now();
    try (PrimeCore core = newCore(CoreConfig.builder().clock(clock).build())) {
      Source<Tick> timer = core.timer("control", Duration.ofMillis(10));
      assertEquals("control", timer.name());
      Reader<Tick> ticks = timer.reader();
      core.start();
      assertEquals(Optional.empty(), ticks.take(quiet()), "virtual time stands still: no tick");
      clock.advance(Duration.ofSeconds(10));
      List<Tick> all = takeOrFail(ticks, 1000);
      for (int i = 0; i < 1000; i++) {
        assertEquals(
            new Tick(i + 1, origin.plusMillis(10L * (i + 1))), all.get(i), "tick " + (i + 1));
      }
      assertEquals(Optional.empty(), ticks.take(quiet()), "the 1001st tick is due at 10.01 s");
      clock.advance(Duration.ofMillis(25));
      assertEquals(
          List.of(new Tick(1001, origin.plusMillis(10_010)), new Tick(1002, origin.plusMillis(10_020))),
          takeOrFail(ticks, 2));
    }
  }

  /**
   * A timer's tick {@code n} is due {@code n} periods after the start and is published then, not
   * earlier ({@link PrimeCore#timer}; architecture.md, "What every media keeps", <i>Timers and the
   * clock</i>), also for the longest periods a timer takes: with a period of a century on a
   * virtual clock advanced by two centuries, ticks 1 and 2 come, each with its due time, and tick
   * 3, due in the third century, does not.
   */
  @Test
  default void aTimerOfACenturyPublishesNoTickBeforeItIsDue() throws InterruptedException {
    VirtualClock clock = new VirtualClock();
    Instant origin = clock.now();
    Duration century = Duration.ofDays(36_525);
    try (PrimeCore core = newCore(CoreConfig.builder().clock(clock).build())) {
      Reader<Tick> ticks = core.timer("century", century).reader();
      core.start();
      clock.advance(century.multipliedBy(2));
      assertEquals(
          List.of(new Tick(1, origin.plus(century)), new Tick(2, origin.plus(century.multipliedBy(2)))),
          takeOrFail(ticks, 2));
      assertEquals(Optional.empty(), ticks.take(quiet()), "tick 3 is due in the third century");
    }
  }

  /**
   * {@link PrimeCore#timer}: a period is "positive, at most {@code Long.MAX_VALUE} nanoseconds",
   * and "tick {@code n} is due {@code n} periods after the core starts". A timer of the longest
   * period on a {@link VirtualClock} advanced to the last reading a clock holds ({@link
   * VirtualClock#advance}: "at most {@code Long.MAX_VALUE} nanoseconds") publishes its first tick,
   * stamped one period after the start, and no other: tick 2 is due past the end of the clock. A
   * sampler of that period likewise publishes its first period's value and nothing of its
   * second. Both end when the core closes.
   */
  @Test
  default void aTimerOfTheLongestPeriodTicksOnceWhenTheClockReachesItsEnd()
      throws InterruptedException {
    VirtualClock clock = new VirtualClock();
    Instant origin = clock.now();
    Duration longest = Duration.ofNanos(Long.MAX_VALUE);
    PrimeCore core = newCore(CoreConfig.builder().clock(clock).metrics(true).build());
    try (core) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Tick> ticks = core.timer("longest", longest).reader();
      Reader<Integer> sampled = core.source("values", events).sample(longest).reader();
      core.start();
      events.publish(1);
      awaitValuesIn(core, "sample(values)", 1); // 1 is in the first period, wherever it travels
      clock.advance(longest);
      assertEquals(new Tick(1, origin.plus(longest)), takeOrFail(ticks));
      assertEquals(1, takeOrFail(sampled), "the first period ended");
      events.publish(2);
      awaitValuesIn(core, "sample(values)", 2); // 2 is in the second period
      assertEquals(Optional.empty(), ticks.take(quiet()), "tick 2 is due past the clock's end");
      assertEquals(Optional.empty(), sampled.take(quiet()), "period 2 ends past the clock's end");
    }
    awaitNoThreadsLeft(core); // the timer waiting for a tick that never comes ended at close
  }

  /**
   * A tick due at a time no {@link Instant} holds (a clock started near {@link Instant#MAX}) is
   * never due, as one past the clock's last reading: the timer's thread waits for the close
   * rather than dying with the time's overflow.
   */
  @Test
  default void aTimerWhoseNextTickFallsPastTheLastInstantWaitsForTheClose()
      throws InterruptedException {
    Instant origin = Instant.MAX.minusMillis(1500);
    VirtualClock clock = new VirtualClock(origin);
    Duration second = Duration.ofSeconds(1);
    BlockingQueue<Throwable> died = new LinkedBlockingQueue<>();
    Thread.UncaughtExceptionHandler before = Thread.getDefaultUncaughtExceptionHandler();
    Thread.setDefaultUncaughtExceptionHandler((thread, error) -> died.add(error));
    try {
      PrimeCore core = newCore(CoreConfig.builder().clock(clock).build());
      try (core) {
        Reader<Tick> ticks = core.timer("last", second).reader();
        core.start();
        clock.advance(second);
        assertEquals(new Tick(1, origin.plus(second)), takeOrFail(ticks));
        clock.advance(second);
        assertEquals(Optional.empty(), ticks.take(quiet()), "tick 2 falls past Instant.MAX");
        assertEquals(List.of(), List.copyOf(died), "no thread of the core died");
      }
      awaitNoThreadsLeft(core);
    } finally {
      Thread.setDefaultUncaughtExceptionHandler(before);
    }
  }

  /** Waits, bounded by {@link #patience()}, until the service named took {@code count} values. */
  private void awaitValuesIn(PrimeCore core, String service, long count) throws InterruptedException {
    long deadline = System.nanoTime() + patience().toNanos();
    CountDownLatch never = new CountDownLatch(1);
    while (core.metrics().service(service).valuesIn() < count && System.nanoTime() < deadline) {
      never.await(5, TimeUnit.MILLISECONDS); // a bounded pause between two looks
    }
    assertEquals(count, core.metrics().service(service).valuesIn(), service + " took " + count + " values");
  }

  @Test
  default void timerTicksOnTheSystemClockOnePeriodApart() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      Reader<Tick> ticks = core.timer("beat", Duration.ofMillis(20)).reader();
      core.start();
      List<Tick> five = takeOrFail(ticks, 5);
      for (int i = 0; i < 5; i++) {
        assertEquals(i + 1, five.get(i).count());
        assertEquals(
            Duration.ofMillis(20L * i),
            Duration.between(five.get(0).time(), five.get(i).time()),
            "ticks are due exactly one period apart");
      }
    }
  }

  /**
   * A config whose publishes give up after 200 ms and whose error handler adds each failure to
   * {@code failures} as (service name, input, error).
   */
  private static CoreConfig shortPublishCollectingFailures(BlockingQueue<List<Object>> failures) {
    return CoreConfig.builder()
        .publishTimeout(Duration.ofMillis(200))
        .errorHandler((service, input, error) -> failures.add(List.of(service, input, error)))
        .build();
  }

  /**
   * {@link Tick#count()} and {@link PrimeCore#timer}: the timer numbers its ticks 1, 2, ... and
   * never skips a number as it catches up, but "a tick whose publish fails ... is not retried": a
   * listener of the timer sees the counts in order, without the ones whose publish failed (each
   * told to the error handler with its count), so those are gaps in what it sees; the timer goes
   * on after such a tick.
   */
  @Test
  default void aTickThatCannotBePublishedGoesToTheErrorHandlerIsAGapAndTheTimerGoesOn()
      throws InterruptedException {
    BlockingQueue<List<Object>> failures = new LinkedBlockingQueue<>();
    CountDownLatch release = new CountDownLatch(1);
    AtomicLong failedTick = new AtomicLong(Long.MAX_VALUE);
    CountDownLatch laterTick = new CountDownLatch(1);
    List<Long> seen = new java.util.concurrent.CopyOnWriteArrayList<>();
    CoreConfig config = shortPublishCollectingFailures(failures);
    try (PrimeCore core = newCoreWithServiceInputCapacity(config, 2)) {
      core.timer("beat", Duration.ofMillis(10))
          .listen(
              tick -> {
                seen.add(tick.count());
                if (tick.count() > failedTick.get()) {
                  laterTick.countDown();
                }
                try {
                  release.await(); // stuck until the test lets it go: its input fills up
                } catch (InterruptedException e) {
                  Thread.currentThread().interrupt();
                }
              });
      core.start();
      try {
        List<Object> failure = failures.poll(patience().toMillis(), TimeUnit.MILLISECONDS);
        assertTrue(failure != null, "no tick failed within " + patience());
        assertEquals("beat", failure.get(0), "the timer's name");
        assertTrue(failure.get(1) instanceof Long, "the tick's count: " + failure.get(1));
        assertTrue(failure.get(2) instanceof QueueFullException, String.valueOf(failure.get(2)));
        failedTick.set((Long) failure.get(1));
      } finally {
        release.countDown();
      }
      assertTrue(
          laterTick.await(patience().toMillis(), TimeUnit.MILLISECONDS),
          "the timer goes on after a tick it could not publish");
    }
    List<Long> heard = List.copyOf(seen);
    assertTrue(heard.size() >= 2, "heard " + heard);
    for (int i = 1; i < heard.size(); i++) {
      assertTrue(heard.get(i - 1) < heard.get(i), "counts in order: " + heard);
    }
    assertFalse(heard.contains(failedTick.get()), "the failed tick is a gap: " + heard);
    assertEquals(1L, heard.get(0), "the first tick is 1");
  }

  /**
   * A timer is a service, and a service's failure goes to the error handler and the service goes
   * on (architecture.md, <i>Generic services</i>, "Failures"): a {@link PrimeClock} whose {@code
   * sleepUntil} throws does not end the timer's thread silently. The handler gets each failure
   * under the timer's name with the count of the tick it was waiting for, and once the clock
   * works again that tick and the next are published, none skipped.
   */
  @Test
  default void aClockThatFailsGoesToTheErrorHandlerAndTheTimerGoesOn()
      throws InterruptedException {
    VirtualClock virtual = new VirtualClock();
    Instant origin = virtual.now();
    AtomicInteger failuresLeft = new AtomicInteger(2);
    PrimeClock failing =
        new PrimeClock() {
          @Override
          public long nanoTime() {
            return virtual.nanoTime();
          }

          @Override
          public void sleepNanos(long nanos) throws InterruptedException {
            virtual.sleepNanos(nanos);
          }

          @Override
          public void sleepUntil(long deadline) throws InterruptedException {
            if (failuresLeft.getAndDecrement() > 0) {
              throw new IllegalStateException("the clock's device is gone");
            }
            virtual.sleepUntil(deadline);
          }

          @Override
          public Instant now() {
            return virtual.now();
          }
        };
    BlockingQueue<List<Object>> failures = new LinkedBlockingQueue<>();
    CoreConfig config =
        CoreConfig.builder()
            .clock(failing)
            .errorHandler((service, input, error) -> failures.add(List.of(service, input, error)))
            .build();
    try (PrimeCore core = newCore(config)) {
      Reader<Tick> ticks = core.timer("beat", Duration.ofMillis(10)).reader();
      core.start();
      for (int i = 1; i <= 2; i++) {
        List<Object> failure = failures.poll(patience().toMillis(), TimeUnit.MILLISECONDS);
        assertTrue(failure != null, "clock failure " + i + " not reported within " + patience());
        assertEquals("beat", failure.get(0), "the timer's name");
        assertEquals(1L, failure.get(1), "the count of the tick it waited for");
        assertTrue(failure.get(2) instanceof IllegalStateException, String.valueOf(failure.get(2)));
      }
      virtual.advance(Duration.ofMillis(20));
      assertEquals(
          List.of(new Tick(1, origin.plusMillis(10)), new Tick(2, origin.plusMillis(20))),
          takeOrFail(ticks, 2),
          "the timer goes on once its clock works again");
    }
  }

  /**
   * CombinedInputs: "Failures of a step go to the error handler under the combinator's name, like
   * any service's". A merge's publish that finds its output's service input full fails after the
   * publish timeout: the handler gets the merge's name, the value and the {@link
   * QueueFullException}; the refused value is published to nobody, and the merge goes on.
   */
  @Test
  default void aCombinedValueThatCannotBePublishedGoesToTheErrorHandlerAndTheCombinatorGoesOn()
      throws InterruptedException {
    BlockingQueue<List<Object>> failures = new LinkedBlockingQueue<>();
    CountDownLatch inside = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    CountDownLatch laterValue = new CountDownLatch(1);
    List<Integer> out = new java.util.concurrent.CopyOnWriteArrayList<>();
    CoreConfig config = shortPublishCollectingFailures(failures);
    try (PrimeCore core = newCoreWithServiceInputCapacity(config, 2)) {
      EventBlock<Integer> a = new EventBlock<>();
      EventBlock<Integer> b = new EventBlock<>();
      Source<Integer> merged = core.merge(core.source("a", a), core.source("b", b));
      merged
          .then(stuckChain(core, "stuck", inside, release))
          .listen(
              x -> {
                out.add(x);
                if (x == 4) {
                  laterValue.countDown();
                }
              });
      core.start();
      try {
        fillStuckInput(a, inside, 2); // 0 held by the chain, 1 and 2 fill its input
        a.publish(3); // the merge takes it; its publish finds no room
        List<Object> failure = failures.poll(patience().toMillis(), TimeUnit.MILLISECONDS);
        assertTrue(failure != null, "no failure reached the error handler within " + patience());
        assertEquals(merged.name(), failure.get(0), "the combinator's name");
        assertEquals(3, failure.get(1), "the value it could not publish");
        assertTrue(failure.get(2) instanceof QueueFullException, String.valueOf(failure.get(2)));
      } finally {
        release.countDown();
      }
      b.publish(4);
      assertTrue(
          laterValue.await(patience().toMillis(), TimeUnit.MILLISECONDS),
          "the merge goes on after a value it could not publish");
      assertEquals(List.of(0, 1, 2, 4), out, "the refused value reached nobody");
    }
  }

  @Test
  default void conflatedReaderReturnsOnlyTheNewestValue() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("pose", events);
      Reader<Integer> latest = source.conflatedReader();
      core.start();
      for (int i = 1; i <= 5; i++) {
        events.publish(i);
      }
      assertEquals(5, takeOrFail(latest));
      assertEquals(Optional.empty(), latest.poll());
      events.publish(6);
      events.publish(7);
      assertEquals(List.of(7), latest.drain());
      events.publish(8);
      events.publish(9);
      assertEquals(Optional.of(9), latest.poll());
      assertEquals(List.of(), latest.drain());
      assertEquals(0, latest.missed());
    }
  }

  @Test
  default void combinatorsAndTimersAreServicesOfTheTopology() {
    try (PrimeCore core = newCore()) {
      Source<Integer> a = core.source("a", new EventBlock<>());
      Source<Integer> b = core.source("b", new EventBlock<>());
      core.combineLatest(a, b);
      core.zip(a, b);
      core.merge(a, b);
      a.withLatestFrom(b);
      a.sample(Duration.ofSeconds(1));
      core.timer("tick", Duration.ofMillis(10));
      a.conflatedReader();
      Topology topology = core.topology();
      assertEquals(
          List.of(
              new TopologyNode.Combinator("combineLatest(a|b)", "combineLatest", List.of("a", "b")),
              new TopologyNode.Combinator("zip(a|b)", "zip", List.of("a", "b")),
              new TopologyNode.Combinator("merge(a|b)", "merge", List.of("a", "b")),
              new TopologyNode.Combinator(
                  "withLatestFrom(a|b)", "withLatestFrom", List.of("a", "b")),
              new TopologyNode.Combinator("sample(a)", "sample", List.of("a")),
              new TopologyNode.Timer("tick", Duration.ofMillis(10)),
              new TopologyNode.ReaderNode("a", 1)),
          topology.nodes().subList(2, topology.nodes().size()));
      assertEquals(
          List.of(
              "combineLatest(a|b)",
              "zip(a|b)",
              "merge(a|b)",
              "withLatestFrom(a|b)",
              "sample(a)",
              "tick"),
          List.copyOf(core.serviceNames()));
      String mermaid = topology.toMermaid();
      assertTrue(mermaid.contains("n3[(\"combineLatest(a|b)\")]"), mermaid);
      assertTrue(mermaid.contains("n8([\"tick\"])"), mermaid);
      assertTrue(mermaid.contains("n1 --> n3\n  n2 --> n3\n"), mermaid);
      String dot = topology.toDot();
      assertTrue(dot.contains("n3 [label=\"combineLatest(a|b)\", shape=cylinder];"), dot);
      assertTrue(dot.contains("n8 [label=\"tick\", shape=invhouse];"), dot);
    }
  }

  @Test
  default void combinesASourceOfAnotherCore() throws InterruptedException {
    try (PrimeCore other = newCore();
        PrimeCore core = newCore()) {
      EventBlock<Integer> remoteEvents = new EventBlock<>();
      EventBlock<String> localEvents = new EventBlock<>();
      Source<Integer> remote = other.source("remote", remoteEvents);
      Source<Tuple2<String, Integer>> both =
          core.combineLatest(core.source("local", localEvents), remote);
      assertEquals("combineLatest(local|remote)", both.name());
      assertEquals(
          new TopologyNode.ForeignSource("from(" + other.name() + ":remote)", other.name(), "remote"),
          core.topology().nodes().get(1));
      Reader<Tuple2<String, Integer>> out = both.reader();
      other.start();
      core.start();
      localEvents.publish("x");
      remoteEvents.publish(1);
      assertEquals(new Tuple2<>("x", 1), takeOrFail(out));
      remoteEvents.publish(2);
      assertEquals(new Tuple2<>("x", 2), takeOrFail(out));
    }
  }

  @Test
  default void combinedSourcesFeedChainsLikeAnyOtherSource() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> aEvents = new EventBlock<>();
      EventBlock<Integer> bEvents = new EventBlock<>();
      Reader<Integer> sums =
          core.zip(core.source("a", aEvents), core.source("b", bEvents))
              .then(core.chain("sum", (Tuple2<Integer, Integer> t) -> t.first() + t.second()))
              .reader();
      core.start();
      for (int i = 1; i <= 10; i++) {
        aEvents.publish(i);
        bEvents.publish(100 * i);
      }
      List<Integer> expected = new ArrayList<>();
      for (int i = 1; i <= 10; i++) {
        expected.add(101 * i);
      }
      assertEquals(expected, takeOrFail(sums, 10));
    }
  }

  @Test
  default void closeStopsCombinatorsAndTimersAndWakesTheirReaders() throws Exception {
    PrimeCore core = newCore();
    EventBlock<Integer> events = new EventBlock<>();
    Source<Integer> a = core.source("a", events);
    Reader<Tuple2<Integer, Integer>> zipped = core.zip(a, a.filter(x -> true)).reader();
    Reader<Tick> ticks = core.timer("tick", Duration.ofMillis(5)).reader();
    core.start();
    events.publish(1);
    assertEquals(new Tuple2<>(1, 1), takeOrFail(zipped));
    takeOrFail(ticks);
    core.close();
    assertThrows(CoreClosedException.class, zipped::take);
    assertThrows(CoreClosedException.class, ticks::take);
    ConformanceBase.assertNoThreadsLeft(core);
  }

  @Test
  default void badArgumentsAreRefusedClearlyAndChangeNothing() {
    try (PrimeCore core = newCore()) {
      Source<Integer> a = core.source("a", new EventBlock<>());
      NullPointerException nullSource =
          assertThrows(NullPointerException.class, () -> core.combineLatest(a, null));
      assertTrue(nullSource.getMessage().contains("source argument 2"), nullSource.getMessage());
      assertThrows(IllegalArgumentException.class, () -> core.merge());
      IllegalArgumentException zero =
          assertThrows(IllegalArgumentException.class, () -> core.timer("t", Duration.ZERO));
      assertTrue(zero.getMessage().contains("positive"), zero.getMessage());
      assertThrows(IllegalArgumentException.class, () -> a.sample(Duration.ofMillis(-1)));
      Duration longest = Duration.ofSeconds(Long.MAX_VALUE);
      IllegalArgumentException tooLong =
          assertThrows(IllegalArgumentException.class, () -> core.timer("t", longest));
      assertTrue(tooLong.getMessage().contains("292 years"), tooLong.getMessage());
      assertThrows(IllegalArgumentException.class, () -> a.sample(longest));
      assertThrows(NullPointerException.class, () -> core.timer(null, Duration.ofSeconds(1)));
      assertThrows(IllegalArgumentException.class, () -> core.timer("a", Duration.ofSeconds(1)));
      assertEquals(List.of(), List.copyOf(core.serviceNames()), "a refused call records nothing");
    }
    PrimeCore closed = newCore();
    Source<Integer> a = closed.source("a", new EventBlock<>());
    closed.close();
    assertThrows(CoreClosedException.class, () -> closed.timer("t", Duration.ofSeconds(1)));
    assertThrows(CoreClosedException.class, () -> closed.merge(a));
  }

  /**
   * A timer declared on a started core counts its periods from its declaration, by the core's
   * clock: on a {@code VirtualClock}, tick {@code n} is due and stamped {@code n} periods after
   * the declaration, and nothing is published for the time before it (architecture,
   * <i>Combinators, timers and the clock</i>, "Timers").
   */
  @Test
  default void aTimerDeclaredOnAStartedCoreTicksFromItsDeclaration() throws InterruptedException {
    VirtualClock clock = new VirtualClock();
    try (PrimeCore core = newCore(CoreConfig.builder().clock(clock).build())) {
      core.start();
      clock.advance(Duration.ofSeconds(3));
      Instant declared = clock.now();
      Reader<Tick> ticks = core.timer("late", Duration.ofMillis(100)).reader();
      assertEquals(Optional.empty(), ticks.take(quiet()), "no tick for the time before the declaration");
      clock.advance(Duration.ofMillis(250));
      assertEquals(
          List.of(new Tick(1, declared.plusMillis(100)), new Tick(2, declared.plusMillis(200))),
          takeOrFail(ticks, 2));
      assertEquals(Optional.empty(), ticks.take(quiet()), "tick 3 is due 300 ms after the declaration");
      clock.advance(Duration.ofMillis(50));
      assertEquals(new Tick(3, declared.plusMillis(300)), takeOrFail(ticks));
    }
  }

  /**
   * A source that runs ahead waits in the zip, at most {@code sourceRetention()} values per
   * source; a value that finds its source's buffer full drops that source's oldest unpaired value,
   * so the pairing is n-th with n-th among the values kept (architecture, <i>Combinators, timers
   * and the clock</i>, {@code zip}). The drops are logged at WARN like failures: the first in
   * full, the rest counted, and what is still counted when the core closes is written then.
   */
  @Test
  default void aZipKeepsAtMostTheRetentionPerSourceAndDropsTheOldestUnpaired()
      throws InterruptedException {
    int retention = 4;
    CoreConfig config = CoreConfig.builder().sourceRetention(retention).metrics(true).build();
    String zipName;
    List<String> lines;
    try (CapturedStderr err = new CapturedStderr()) {
      try (PrimeCore core = newCore(config)) {
        EventBlock<Integer> aEvents = new EventBlock<>();
        EventBlock<String> bEvents = new EventBlock<>();
        Source<Tuple2<Integer, String>> zipped =
            core.zip(core.source("a", aEvents), core.source("b", bEvents));
        Reader<Tuple2<Integer, String>> out = zipped.reader();
        core.start();
        for (int i = 1; i <= retention + 3; i++) {
          aEvents.publish(i);
          awaitProcessed(core, zipped.name(), i); // one by one: the zip's input never lags
        }
        List<String> words = List.of("w", "x", "y", "z");
        for (String word : words) {
          bEvents.publish(word);
        }
        List<Tuple2<Integer, String>> expected = new ArrayList<>();
        for (int i = 0; i < retention; i++) {
          expected.add(new Tuple2<>(4 + i, words.get(i))); // 1, 2 and 3 were dropped
        }
        assertEquals(expected, takeOrFail(out, retention));
        assertEquals(Optional.empty(), out.take(quiet()), "nothing of a is left unpaired");
        zipName = zipped.name();
      }
      lines = err.lines();
    }
    List<String> drops =
        lines.stream().filter(l -> l.contains("zip '" + zipName + "' dropped")).toList();
    assertEquals(2, drops.size(), "the first drop, then the rest at close:\n" + lines);
    assertTrue(drops.get(0).contains("dropped the oldest unpaired value of input 1"), drops.get(0));
    assertTrue(drops.get(1).contains("2 more in the last"), "the other two drops: " + drops.get(1));
  }

  /** Waits, bounded by the kit's patience, until the metered node processed {@code count} values. */
  private void awaitProcessed(PrimeCore core, String name, long count) throws InterruptedException {
    long deadline = System.nanoTime() + patience().toNanos();
    long processed;
    while ((processed = core.metrics().service(name).processing().count()) < count) {
      assertTrue(
          System.nanoTime() < deadline, name + " processed " + processed + " of " + count + " values");
      Thread.sleep(1); // polls a counter; the order of the test does not depend on the sleep
    }
  }
}

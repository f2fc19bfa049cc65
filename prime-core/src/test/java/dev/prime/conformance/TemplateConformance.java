package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTimeoutPreemptively;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.EventBlock;
import dev.prime.Isolated;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Repeat;
import dev.prime.Source;
import dev.prime.Token;
import dev.prime.Tuple2;
import dev.prime.Tuple3;
import dev.prime.Tuple4;
import dev.prime.Tuple5;
import java.util.ArrayList;
import java.util.Collections;
import java.util.List;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.ExecutorService;
import java.util.concurrent.Executors;
import java.util.concurrent.Future;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicInteger;
import java.util.stream.IntStream;
import org.junit.jupiter.api.Test;

/** Every template of the paper: if/then/else, forEach, union, fork, guard, isolate, collectors, repeater. */
public interface TemplateConformance extends ConformanceBase {

  @Test
  default void ifThenElseChoosesABranch() {
    try (PrimeCore core = newCore()) {
      Chain<Integer, String> chain =
          core.ifThenElse(x -> x > 0, core.chain(x -> "pos" + x), core.chain(x -> "neg" + x));
      core.start();
      Block<Integer, String> block = chain.toBlock();
      assertEquals("pos3", block.process(3));
      assertEquals("neg-3", block.process(-3));
    }
  }

  @Test
  default void forEachMapsEveryElementInOrder() {
    try (PrimeCore core = newCore()) {
      Chain<List<Integer>, List<Integer>> chain = core.forEach(core.chain(x -> x * x));
      core.start();
      Block<List<Integer>, List<Integer>> block = chain.toBlock();
      assertEquals(List.of(1, 4, 9), block.process(List.of(1, 2, 3)));
      assertEquals(List.of(), block.process(List.of()));
    }
  }

  /**
   * {@link PrimeCore#forEach}: a {@code null} list is refused with an exception that says so
   * (somewhere in its chain of causes, as a media may wrap the block's failure), and the body is
   * not run.
   */
  @Test
  default void forEachRefusesANullListClearly() {
    try (PrimeCore core = newCore()) {
      java.util.concurrent.atomic.AtomicInteger runs = new java.util.concurrent.atomic.AtomicInteger();
      Chain<List<Integer>, List<Integer>> chain =
          core.forEach(core.chain(x -> { runs.incrementAndGet(); return x; }));
      core.start();
      Block<List<Integer>, List<Integer>> block = chain.toBlock();
      RuntimeException e = assertThrows(RuntimeException.class, () -> block.process(null));
      StringBuilder messages = new StringBuilder();
      for (Throwable t = e; t != null; t = t.getCause()) {
        messages.append(t.getMessage()).append(" | ");
      }
      assertTrue(
          messages.toString().contains("for-each input list must not be null"),
          "names the null list: " + messages);
      assertEquals(0, runs.get(), "the body is not run for a null list");
      assertEquals(List.of(2), block.process(List.of(2)), "the chain goes on");
    }
  }

  @Test
  default void unionOfTwoToFive() {
    try (PrimeCore core = newCore()) {
      Chain<Integer, Tuple2<Integer, String>> u2 = core.union(core.chain(x -> x + 1), core.chain(x -> "s" + x));
      Chain<Integer, Tuple3<Integer, Integer, Integer>> u3 =
          core.union(core.chain(x -> x), core.chain(x -> x * 2), core.chain(x -> x * 3));
      Chain<Integer, Tuple4<Integer, Integer, Integer, Integer>> u4 =
          core.union(core.chain(x -> x), core.chain(x -> x * 2), core.chain(x -> x * 3), core.chain(x -> x * 4));
      Chain<Integer, Tuple5<Integer, Integer, Integer, Integer, String>> u5 =
          core.union(
              core.chain(x -> x),
              core.chain(x -> x * 2),
              core.chain(x -> x * 3),
              core.chain(x -> x * 4),
              core.chain(x -> "five" + x));
      core.start();
      assertEquals(new Tuple2<>(2, "s1"), u2.toBlock().process(1));
      assertEquals(new Tuple3<>(2, 4, 6), u3.toBlock().process(2));
      assertEquals(new Tuple4<>(1, 2, 3, 4), u4.toBlock().process(1));
      assertEquals(new Tuple5<>(1, 2, 3, 4, "five1"), u5.toBlock().process(1));
    }
  }

  @Test
  default void forkPublishesOutputsToASource() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> side = new EventBlock<>();
      Reader<Integer> reader = core.source(side).reader();
      Chain<Integer, Integer> chain = core.fork(core.chain(x -> x == 0 ? null : x * 10), side);
      core.start();
      Block<Integer, Integer> block = chain.toBlock();
      assertEquals(10, block.process(1));
      assertEquals(null, block.process(0));
      assertEquals(20, block.process(2));
      assertEquals(List.of(10, 20), takeOrFail(reader, 2));
      assertTrue(reader.poll().isEmpty(), "a fork publishes no null");
    }
  }

  /**
   * {@link Block}, "Nulls": "Chains pass {@code null} between blocks if a block returns it, on
   * every media", also into and out of every template: an if/else chooses on a {@code null} and
   * its branch gets it; each chain of a union gets it and a union's tuple holds a {@code null}
   * output; a for-each's body gets a {@code null} element and its {@code null} output stays in the
   * list; a guard's predicate and substitute get it; an isolated chain's user passes it both ways;
   * a repeater's block sees its inner chain's {@code null} output and may go again with a {@code
   * null} input. The same where the chain runs linked to a source (which publishes nothing only
   * for a {@code null} the whole chain returns).
   */
  @Test
  default void aNullPassesIntoAndOutOfEveryTemplate() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      java.util.function.Function<String, Chain<Integer, Integer>> nullIfNegative =
          name -> core.chain(name, (Integer x) -> x < 0 ? null : x);
      Block<Integer, String> ifElse =
          nullIfNegative
              .apply("n-if")
              .then(
                  core.ifThenElse(
                      (Integer x) -> x == null,
                      core.chain("if-null", (Integer x) -> "null:" + x),
                      core.chain("if-value", (Integer x) -> "value:" + x)))
              .toBlock();
      Block<Integer, Tuple2<String, Integer>> union =
          nullIfNegative
              .apply("n-union")
              .then(
                  core.union(
                      core.chain("union-a", (Integer x) -> x == null ? "a:null" : "a:" + x),
                      core.chain("union-b", (Integer x) -> x)))
              .toBlock();
      Block<List<Integer>, List<Integer>> forEach =
          core.forEach(core.chain("each", (Integer x) -> x == null ? Integer.valueOf(-1) : x == 0 ? null : Integer.valueOf(2 * x)))
              .toBlock();
      Block<Integer, Integer> guard =
          nullIfNegative
              .apply("n-guard")
              .then(
                  core.guard(
                      (Integer x) -> x != null,
                      core.chain("guarded", (Integer x) -> x + 1),
                      (Integer x) -> x == null ? -100 : -200))
              .toBlock();
      Isolated<Integer, Integer> shared =
          core.isolate(core.chain("shared", (Integer x) -> x == null ? null : x * 10));
      Block<Integer, Integer> isolated =
          nullIfNegative.apply("n-isolated").then(shared.newUser()).toBlock();
      Block<Integer, String> repeater =
          core.repeater(
                  core.chain("inner", (Integer x) -> x == null ? null : x - 1),
                  (Integer input, Integer output, List<Void> collected) ->
                      output == null
                          ? Repeat.<Integer, String>stop("stopped on null after " + input)
                          : output == 0 ? Repeat.<Integer, String>again(null) : Repeat.again(output))
              .toBlock();
      EventBlock<Integer> events = new EventBlock<>();
      Reader<String> served =
          core.source("numbers", events)
              .then(
                  nullIfNegative
                      .apply("n-served")
                      .then(
                          core.ifThenElse(
                              (Integer x) -> x == null,
                              core.chain("served-null", (Integer x) -> "served null:" + x),
                              core.chain("served-value", (Integer x) -> "served " + x))))
              .reader();
      core.start();

      assertEquals("null:null", ifElse.process(-1));
      assertEquals("value:4", ifElse.process(4));
      assertEquals(new Tuple2<>("a:null", null), union.process(-1));
      assertEquals(new Tuple2<>("a:5", 5), union.process(5));
      assertEquals(
          java.util.Arrays.asList(2, -1, null, 6), forEach.process(java.util.Arrays.asList(1, null, 0, 3)));
      assertEquals(-100, guard.process(-1));
      assertEquals(8, guard.process(7));
      assertEquals(null, isolated.process(-1));
      assertEquals(30, isolated.process(3));
      assertEquals("stopped on null after null", repeater.process(2));
      events.publish(-1);
      events.publish(2);
      assertEquals(List.of("served null:null", "served 2"), takeOrFail(served, 2));
    }
  }

  @Test
  default void guardSubstitutesWhenThePredicateFails() {
    try (PrimeCore core = newCore()) {
      AtomicInteger guardedCalls = new AtomicInteger();
      Chain<Integer, Integer> chain =
          core.guard(
              x -> x != 0,
              core.chain(
                  x -> {
                    guardedCalls.incrementAndGet();
                    return 100 / x;
                  }),
              x -> -1);
      core.start();
      Block<Integer, Integer> block = chain.toBlock();
      assertEquals(50, block.process(2));
      assertEquals(-1, block.process(0));
      assertEquals(1, guardedCalls.get());
    }
  }

  @Test
  default void isolatedChainIsNeverRunConcurrently() throws Exception {
    int users = 4;
    int callsEach = 50;
    AtomicInteger inside = new AtomicInteger();
    AtomicInteger maxInside = new AtomicInteger();
    AtomicInteger total = new AtomicInteger();
    try (PrimeCore core = newCore()) {
      Isolated<Integer, Integer> isolated =
          core.isolate(
              core.chain(
                  "shared",
                  x -> {
                    int now = inside.incrementAndGet();
                    maxInside.accumulateAndGet(now, Math::max);
                    Thread.yield();
                    total.incrementAndGet();
                    inside.decrementAndGet();
                    return x + 1;
                  }));
      assertEquals("shared", isolated.name());
      List<Block<Integer, Integer>> blocks = new ArrayList<>();
      for (int i = 0; i < users; i++) {
        blocks.add(isolated.newUser().toBlock());
      }
      core.start();
      ExecutorService pool = Executors.newFixedThreadPool(users);
      try {
        CountDownLatch go = new CountDownLatch(1);
        List<Future<Integer>> results = new ArrayList<>();
        for (Block<Integer, Integer> block : blocks) {
          results.add(
              pool.submit(
                  () -> {
                    go.await();
                    int sum = 0;
                    for (int c = 0; c < callsEach; c++) {
                      sum += block.process(c);
                    }
                    return sum;
                  }));
        }
        go.countDown();
        int expectedSum = callsEach * (callsEach + 1) / 2;
        for (Future<Integer> result : results) {
          assertEquals(expectedSum, result.get(patience().toMillis(), TimeUnit.MILLISECONDS));
        }
      } finally {
        pool.shutdownNow();
      }
      assertEquals(users * callsEach, total.get());
      assertEquals(1, maxInside.get(), "the isolated chain ran concurrently");
    }
  }

  @Test
  default void isolatedUserBlockedInsideDelaysTheOthers() throws Exception {
    CountDownLatch entered = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    try (PrimeCore core = newCore()) {
      Isolated<Integer, Integer> isolated =
          core.isolate(
              core.chain(
                  x -> {
                    if (x == 1) {
                      entered.countDown();
                      try {
                        release.await();
                      } catch (InterruptedException e) {
                        Thread.currentThread().interrupt();
                      }
                    }
                    return x;
                  }));
      Block<Integer, Integer> first = isolated.newUser().toBlock();
      Block<Integer, Integer> second = isolated.newUser().toBlock();
      core.start();
      ExecutorService pool = Executors.newFixedThreadPool(2);
      try {
        Future<Integer> holder = pool.submit(() -> first.process(1));
        assertTrue(entered.await(patience().toMillis(), TimeUnit.MILLISECONDS));
        Future<Integer> waiter = pool.submit(() -> second.process(2));
        assertTrue(!waiter.isDone(), "second user entered while the first was inside");
        release.countDown();
        assertEquals(1, holder.get(patience().toMillis(), TimeUnit.MILLISECONDS));
        assertEquals(2, waiter.get(patience().toMillis(), TimeUnit.MILLISECONDS));
      } finally {
        release.countDown();
        pool.shutdownNow();
      }
    }
  }

  /**
   * {@link Isolated#newUser()} "creates a chain for one more user of the shared chain", also on a
   * started core, where "services declared after start() start at once": a user made after the
   * start and called, and one made after the start and linked to a source, share the chain with a
   * user made before, never inside it together with the earlier user, and each gets its results.
   */
  @Test
  default void anIsolatedChainTakesNewUsersAfterTheStart() throws Exception {
    try (PrimeCore core = newCore()) {
      CountDownLatch entered = new CountDownLatch(1);
      CountDownLatch release = new CountDownLatch(1);
      AtomicInteger inside = new AtomicInteger();
      AtomicInteger overlaps = new AtomicInteger();
      Isolated<Integer, Integer> isolated =
          core.isolate(
              core.chain(
                  "late-shared",
                  (Integer x) -> {
                    if (inside.incrementAndGet() > 1) {
                      overlaps.incrementAndGet();
                    }
                    try {
                      if (x == 1) {
                        entered.countDown();
                        release.await(patience().toMillis(), TimeUnit.MILLISECONDS);
                      }
                    } catch (InterruptedException e) {
                      Thread.currentThread().interrupt();
                    } finally {
                      inside.decrementAndGet();
                    }
                    return x * 10;
                  }));
      Block<Integer, Integer> early = isolated.newUser().toBlock();
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> requests = core.source("requests", events);
      core.start();
      Block<Integer, Integer> late = isolated.newUser().toBlock();
      Reader<Integer> linked = requests.then(isolated.newUser()).reader();
      ExecutorService pool = Executors.newFixedThreadPool(2);
      try {
        Future<Integer> holder = pool.submit(() -> early.process(1));
        assertTrue(entered.await(patience().toMillis(), TimeUnit.MILLISECONDS));
        Future<Integer> waiter = pool.submit(() -> late.process(2));
        events.publish(3);
        release.countDown();
        assertEquals(10, holder.get(patience().toMillis(), TimeUnit.MILLISECONDS));
        assertEquals(20, waiter.get(patience().toMillis(), TimeUnit.MILLISECONDS));
        assertEquals(30, takeOrFail(linked));
        assertEquals(40, late.process(4));
      } finally {
        release.countDown();
        pool.shutdownNow();
      }
      assertEquals(0, overlaps.get(), "the users were never inside together");
    }
  }

  @Test
  default void syncCollectorReturnsTheNextValueEachCall() throws Exception {
    try (PrimeCore core = newCore()) {
      EventBlock<String> events = new EventBlock<>();
      Chain<Token, String> collector = core.syncCollector(core.source(events));
      core.start();
      Block<Token, String> block = collector.toBlock();
      events.publish("x");
      events.publish("y");
      assertEquals("x", block.process(Token.INSTANCE));
      assertEquals("y", block.process(Token.INSTANCE));
      ExecutorService pool = Executors.newSingleThreadExecutor();
      try {
        Future<String> waiting = pool.submit(() -> block.process(Token.INSTANCE));
        events.publish("z");
        assertEquals("z", waiting.get(patience().toMillis(), TimeUnit.MILLISECONDS));
      } finally {
        pool.shutdownNow();
      }
    }
  }

  @Test
  default void asyncCollectorReturnsEverythingSinceItsLastCall() {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Chain<Token, List<Integer>> collector = core.asyncCollector(core.source(events));
      core.start();
      Block<Token, List<Integer>> block = collector.toBlock();
      assertEquals(List.of(), block.process(Token.INSTANCE));
      events.publish(1);
      events.publish(2);
      assertEquals(List.of(1, 2), block.process(Token.INSTANCE));
      events.publish(3);
      assertEquals(List.of(3), block.process(Token.INSTANCE));
      assertEquals(List.of(), block.process(Token.INSTANCE));
    }
  }

  @Test
  default void repeaterWithoutSourceLoopsUntilStop() {
    try (PrimeCore core = newCore()) {
      AtomicInteger rounds = new AtomicInteger();
      Chain<Integer, String> chain =
          core.repeater(
              core.chain(
                  x -> {
                    rounds.incrementAndGet();
                    return x * 2;
                  }),
              (Integer in, Integer out, List<Void> none) ->
                  out >= 100 ? Repeat.stop("done:" + out) : Repeat.again(out));
      core.start();
      assertEquals("done:128", chain.toBlock().process(1));
      assertEquals(7, rounds.get());
    }
  }

  /**
   * {@link dev.prime.RepeaterBlock#next}: "never {@code null}". A repeater block that returns
   * {@code null} fails the call with a {@link NullPointerException} that says what to return
   * instead (not an NPE from deep inside the loop, and not a conclusion of {@code null}), and
   * the repeater chain keeps working for the next call.
   */
  @Test
  default void aRepeaterBlockThatReturnsNullFailsTheCallClearlyAndTheChainGoesOn() {
    try (PrimeCore core = newCore()) {
      Chain<Integer, String> chain =
          core.repeater(
              core.chain(x -> x + 1),
              (Integer in, Integer out, List<Void> none) ->
                  in < 0 ? null : out >= 3 ? Repeat.stop("done:" + out) : Repeat.again(out));
      core.start();
      Block<Integer, String> block = chain.toBlock();
      RuntimeException failed = assertThrows(RuntimeException.class, () -> block.process(-5));
      Throwable npe = failed;
      StringBuilder causes = new StringBuilder();
      while (npe != null && !(npe instanceof NullPointerException)) {
        causes.append(npe).append(" <- ");
        npe = npe.getCause() == npe ? null : npe.getCause();
      }
      assertTrue(npe != null, "a NullPointerException ends the call, not: " + causes);
      assertTrue(
          String.valueOf(npe.getMessage()).contains("returned null")
              && npe.getMessage().contains("Repeat.stop"),
          "the exception says what the repeater block should return: " + npe.getMessage());
      assertEquals("done:3", block.process(0), "the repeater chain keeps working");
    }
  }

  /**
   * {@link PrimeCore#repeater(Chain, dev.prime.RepeaterBlock)}: the repeater block's "{@code
   * collected} list is always empty" for a repeater without a source (an empty list, not {@code
   * null}), every round.
   */
  @Test
  default void aRepeaterWithoutASourceSeesAnEmptyCollectedListEveryRound() {
    try (PrimeCore core = newCore()) {
      List<String> seen = new CopyOnWriteArrayList<>();
      Chain<Integer, Integer> chain =
          core.repeater(
              core.chain(x -> x + 1),
              (Integer in, Integer out, List<Void> none) -> {
                seen.add(String.valueOf(none));
                return out >= 3 ? Repeat.stop(out) : Repeat.again(out);
              });
      core.start();
      assertEquals(3, chain.toBlock().process(0));
      assertEquals(List.of("[]", "[]", "[]"), seen, "each of the three rounds saw an empty list");
    }
  }

  @Test
  default void repeaterWithSourceSeesCollectedValues() {
    try (PrimeCore core = newCore()) {
      EventBlock<String> events = new EventBlock<>();
      Source<String> commands = core.source(events);
      List<List<String>> seen = new ArrayList<>();
      Chain<Integer, Integer> chain =
          core.repeater(
              core.chain(
                  x -> {
                    if (x == 2) {
                      events.publish("stop");
                    }
                    return x + 1;
                  }),
              commands,
              (Integer in, Integer out, List<String> collected) -> {
                seen.add(collected);
                return collected.contains("stop") ? Repeat.stop(out) : Repeat.again(out);
              });
      core.start();
      events.publish("hello");
      assertEquals(3, chain.toBlock().process(0));
      assertEquals(List.of(List.of("hello"), List.of(), List.of("stop")), seen);
    }
  }

  @Test
  default void templatesCompose() {
    try (PrimeCore core = newCore()) {
      Chain<List<Integer>, List<String>> chain =
          core.forEach(
              core.ifThenElse(
                  x -> x % 2 == 0,
                  core.link(core.chain(x -> x / 2), core.chain(x -> "half" + x)),
                  core.guard(x -> x > 0, core.chain(x -> "odd" + x), x -> "neg")));
      core.start();
      assertEquals(List.of("half1", "odd3", "neg"), chain.toBlock().process(List.of(2, 3, -1)));
    }
  }

  /**
   * {@link PrimeCore#syncCollector}: "Its reader is created now, so it sees the values retained
   * now and everything later"; {@link PrimeCore#asyncCollector}: "at the first call: the values
   * retained when the collector was made, and later ones". Collectors made on a started core,
   * after values were published to an event source and to a service's output, return those
   * values first, then the later ones.
   */
  @Test
  default void collectorsMadeLateSeeTheValuesRetainedWhenTheyWereMade()
      throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("early", events);
      Source<Integer> output = source.then(core.chain("negate", (Integer x) -> -x));
      Reader<Integer> pacer = output.reader();
      core.start();
      events.publish(1);
      events.publish(2);
      assertEquals(List.of(-1, -2), takeOrFail(pacer, 2));
      for (Source<Integer> collected : List.of(source, output)) {
        int sign = collected == source ? 1 : -1;
        Block<Token, Integer> next = core.syncCollector(collected).toBlock();
        Block<Token, List<Integer>> since = core.asyncCollector(collected).toBlock();
        if (collected == source) {
          events.publish(3);
          assertEquals(-3, takeOrFail(pacer));
        }
        List<Integer> expected = List.of(sign, 2 * sign, 3 * sign);
        List<Integer> taken =
            assertTimeoutPreemptively(
                patience(),
                () -> {
                  List<Integer> values = new ArrayList<>();
                  for (int i = 0; i < 3; i++) {
                    values.add(next.process(Token.INSTANCE));
                  }
                  return values;
                },
                collected.name() + ": the sync collector waits for a value it should have");
        assertEquals(expected, taken, collected.name() + ": the sync collector");
        assertEquals(expected, since.process(Token.INSTANCE), collected.name() + ": the async one");
      }
    }
  }

  /**
   * A repeater whose inner chain forks its output to a source and then reads that source with a
   * sync collector gets each round's own output back in the same round ({@link
   * PrimeCore#fork}: the chain "also publishes each output"; {@link PrimeCore#syncCollector}:
   * "the next value of {@code source} on each call"), and its own source, published by another
   * thread while it loops, is collected whole: over the rounds the {@code collected} lists hold
   * every value once, in order ({@link PrimeCore#asyncCollector}: "every value ... published
   * since its previous call"). The repeater stops once it has run at least 20 rounds and
   * collected the last of the 200 values.
   */
  @Test
  default void aRepeaterReadsBackItsForkedOutputEachRoundAndCollectsABusySourceWhole()
      throws Exception {
    int produced = 200;
    int leastRounds = 20;
    ExecutorService producer = Executors.newSingleThreadExecutor();
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> outputs = new EventBlock<>();
      Source<Integer> forked = core.source("forked", outputs);
      EventBlock<Integer> busy = new EventBlock<>();
      Source<Integer> produce = core.source("produced", busy);
      Chain<Integer, Tuple2<Integer, Integer>> round =
          core.link(
              core.fork(core.chain("step", (Integer x) -> x + 1), outputs),
              core.union(
                  core.chain("kept", (Integer x) -> x),
                  core.link(
                      core.chain("ask", (Integer x) -> Token.INSTANCE),
                      core.syncCollector(forked))));
      List<Tuple2<Integer, Integer>> rounds = new CopyOnWriteArrayList<>();
      List<Integer> collected = new CopyOnWriteArrayList<>();
      Chain<Integer, Integer> loop =
          core.repeater(
              round,
              produce,
              (Integer in, Tuple2<Integer, Integer> out, List<Integer> got) -> {
                rounds.add(out);
                collected.addAll(got);
                return rounds.size() < leastRounds || !collected.contains(produced - 1)
                    ? Repeat.again(out.first())
                    : Repeat.stop(out.first());
              });
      core.start();
      Block<Integer, Integer> block = loop.toBlock();
      Future<?> publishing =
          producer.submit(
              () -> {
                for (int i = 0; i < produced; i++) {
                  busy.publish(i);
                }
              });
      int conclusion =
          assertTimeoutPreemptively(
              patience(), () -> block.process(0), "the repeater never collected all values");
      publishing.get(patience().toMillis(), TimeUnit.MILLISECONDS);
      assertEquals(IntStream.range(0, produced).boxed().toList(), collected);
      assertEquals(rounds.size(), conclusion, "one round per step");
      for (int r = 0; r < rounds.size(); r++) {
        assertEquals(
            new Tuple2<>(r + 1, r + 1),
            rounds.get(r),
            "round " + r + ": its output, and the forked output read back");
      }
    } finally {
      producer.shutdownNow();
    }
  }

  /**
   * A repeater's {@code collected} list holds exactly what its source published during that
   * round: an inner chain that publishes its input ten times to the repeater's source sees those
   * ten, and only those, after each round; and another async collector of the same source, made
   * before the repeater ran, returns all of them, in order.
   */
  @Test
  default void eachRoundOfARepeaterCollectsExactlyWhatItsInnerChainPublished() {
    int copies = 10;
    int rounds = 10;
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> echoes = new EventBlock<>();
      Source<Integer> echoed = core.source("echoes", echoes);
      Block<Token, List<Integer>> everything = core.asyncCollector(echoed).toBlock();
      List<String> wrong = new CopyOnWriteArrayList<>();
      Chain<Integer, Integer> loop =
          core.repeater(
              core.chain(
                  "emulator",
                  (Integer x) -> {
                    for (int i = 0; i < copies; i++) {
                      echoes.publish(x);
                    }
                    return x;
                  }),
              echoed,
              (Integer in, Integer out, List<Integer> got) -> {
                if (!got.equals(Collections.nCopies(copies, in))) {
                  wrong.add("round " + in + " collected " + got);
                }
                return out + 1 < rounds ? Repeat.again(out + 1) : Repeat.stop(out + 1);
              });
      core.start();
      assertEquals(rounds, loop.toBlock().process(0));
      assertEquals(List.of(), wrong);
      List<Integer> all = new ArrayList<>();
      for (int r = 0; r < rounds; r++) {
        all.addAll(Collections.nCopies(copies, r));
      }
      assertEquals(all, everything.process(Token.INSTANCE), "the other collector");
    }
  }

  /**
   * Users of an isolated chain linked to one source run as services side by side, yet the shared
   * chain never runs concurrently ({@link PrimeCore#isolate}: "never running it concurrently"),
   * and each user's service processes every value: a union of sync collectors of the three
   * users' outputs returns each published value three times, in publication order.
   */
  @Test
  default void isolatedUsersLinkedToOneSourceEachProcessEveryValueOneAtATime() {
    int values = 20;
    AtomicInteger inside = new AtomicInteger();
    AtomicInteger maxInside = new AtomicInteger();
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> requests = core.source("requests", events);
      Isolated<Integer, Integer> shared =
          core.isolate(
              core.chain(
                  "shared",
                  (Integer x) -> {
                    maxInside.accumulateAndGet(inside.incrementAndGet(), Math::max);
                    Thread.yield();
                    inside.decrementAndGet();
                    return x;
                  }));
      Source<Integer> a = requests.then(shared.newUser());
      Source<Integer> b = requests.then(shared.newUser());
      Source<Integer> c = requests.then(shared.newUser());
      Block<Token, Tuple3<Integer, Integer, Integer>> all =
          core.union(core.syncCollector(a), core.syncCollector(b), core.syncCollector(c)).toBlock();
      core.start();
      for (int i = 0; i < values; i++) {
        events.publish(i);
      }
      List<Tuple3<Integer, Integer, Integer>> triples =
          assertTimeoutPreemptively(
              patience(),
              () -> {
                List<Tuple3<Integer, Integer, Integer>> got = new ArrayList<>();
                for (int i = 0; i < values; i++) {
                  got.add(all.process(Token.INSTANCE));
                }
                return got;
              },
              "a user's service did not process every value");
      for (int i = 0; i < values; i++) {
        assertEquals(new Tuple3<>(i, i, i), triples.get(i), "value " + i);
      }
      assertEquals(1, maxInside.get(), "the isolated chain ran concurrently");
    }
  }
}

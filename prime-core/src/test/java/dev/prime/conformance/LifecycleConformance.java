package dev.prime.conformance;

import static dev.prime.conformance.ConformanceBase.assertNoThreadsLeft;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertNotEquals;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.CoreClosedException;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.QueueFullException;
import dev.prime.Reader;
import dev.prime.Source;
import dev.prime.Token;
import java.time.Duration;
import java.util.List;
import java.util.Optional;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.ExecutorService;
import java.util.concurrent.Executors;
import java.util.concurrent.Future;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicReference;
import org.junit.jupiter.api.Test;

/** Lifecycle and misuse: start/close, leaks, and clear exceptions for bad input. */
public interface LifecycleConformance extends ConformanceBase {

  /** How far under its timeout a timed join may end (it counts whole milliseconds). */
  Duration JOIN_GRANULARITY = Duration.ofMillis(10);

  /**
   * Whether a core's topology outlives it (Optimus: it lives in Redis, and a core started later
   * under the same name on the same Redis carries on); on the in-memory media every core starts
   * empty.
   */
  default boolean topologyOutlivesItsCores() {
    return false;
  }

  /**
   * A core made under the name of a closed core starts empty on the in-memory media: its reader
   * gets only what is published to it. Where the topology outlives its cores ({@link
   * #topologyOutlivesItsCores()}, the Optimus README's "Several processes") it carries on where
   * the closed one stopped: its reader first gets what the source retained from the earlier core,
   * then the new value.
   */
  @Test
  default void aCoreUnderTheNameOfAClosedOneStartsEmptyOrCarriesOnAsItsMediaSays()
      throws InterruptedException {
    CoreConfig config =
        CoreConfig.builder().name("kit-again-" + Long.toString(System.nanoTime(), 36)).build();
    try (PrimeCore first = newCore(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      first.source("numbers", events);
      first.start();
      for (int i = 1; i <= 3; i++) {
        events.publish(i);
      }
    }
    try (PrimeCore second = newCore(config)) {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> reader = second.source("numbers", events).reader();
      second.start();
      events.publish(4);
      List<Integer> expected = topologyOutlivesItsCores() ? List.of(1, 2, 3, 4) : List.of(4);
      assertEquals(expected, takeOrFail(reader, expected.size()));
      assertEquals(Optional.empty(), reader.take(Duration.ofMillis(200)), "nothing more");
    }
  }

  @Test
  default void startAndCloseManyTimesLeavesNoThreads() throws InterruptedException {
    for (int round = 0; round < 30; round++) {
      PrimeCore core = newCore();
      try (core) {
        EventBlock<Integer> events = new EventBlock<>();
        Source<Integer> out = core.link(core.source(events), core.chain(x -> x + 1));
        Reader<Integer> reader = out.reader();
        assertFalse(core.isStarted());
        core.start();
        assertTrue(core.isStarted());
        events.publish(round);
        assertEquals(round + 1, takeOrFail(reader));
      }
      assertTrue(core.isClosed());
      assertNoThreadsLeft(core);
    }
  }

  @Test
  default void closeWithoutStartAndCloseTwice() {
    PrimeCore core = newCore();
    core.link(core.source(new EventBlock<Integer>()), core.chain(x -> x));
    assertFalse(core.isClosed());
    core.close();
    core.close();
    assertTrue(core.isClosed());
    assertFalse(core.isStarted(), "isStarted() is whether start() was called; it was not");
    assertNoThreadsLeft(core);
    assertThrows(CoreClosedException.class, core::start);
    assertFalse(core.isStarted(), "a refused start() does not start the core");
  }

  @Test
  default void closeStopsAServiceBlockedInTakePromptly() throws InterruptedException {
    PrimeCore core = newCore(CoreConfig.builder().shutdownTimeout(Duration.ofSeconds(10)).build());
    try (core) {
      core.link(core.source(new EventBlock<Integer>()), core.chain(x -> x));
      core.start();
    }
    assertNoThreadsLeft(core);
  }

  @Test
  default void closeStopsABusyServiceAndLeavesNoThreads() throws InterruptedException {
    CountDownLatch inside = new CountDownLatch(1);
    PrimeCore core = newCore();
    try (core) {
      EventBlock<Integer> events = new EventBlock<>();
      core.link(
          core.source(events),
          core.chain(
              x -> {
                inside.countDown();
                return x;
              }));
      core.start();
      for (int i = 0; i < 100; i++) {
        events.publish(i);
      }
      assertTrue(inside.await(patience().toMillis(), TimeUnit.MILLISECONDS));
    }
    assertNoThreadsLeft(core);
  }

  @Test
  default void syncCollectorWaitingWhenTheCoreClosesFailsClearly() throws Exception {
    ExecutorService pool = Executors.newSingleThreadExecutor();
    try {
      PrimeCore core = newCore();
      Block<Token, Integer> block;
      try (core) {
        Chain<Token, Integer> collector = core.syncCollector(core.source(new EventBlock<Integer>()));
        core.start();
        block = collector.toBlock();
        CountDownLatch calling = new CountDownLatch(1);
        Future<Integer> waiting =
            pool.submit(
                () -> {
                  calling.countDown();
                  return block.process(Token.INSTANCE);
                });
        assertTrue(calling.await(patience().toMillis(), TimeUnit.MILLISECONDS));
        core.close();
        java.util.concurrent.ExecutionException e =
            assertThrows(
                java.util.concurrent.ExecutionException.class,
                () -> waiting.get(patience().toMillis(), TimeUnit.MILLISECONDS));
        assertTrue(
            e.getCause() instanceof CoreClosedException
                || e.getCause().getCause() instanceof CoreClosedException,
            "a caller blocked on a closed core gets CoreClosedException: " + e.getCause());
      }
      assertNoThreadsLeft(core);
    } finally {
      pool.shutdownNow();
    }
  }

  @Test
  default void startTwiceIsRefused() {
    try (PrimeCore core = newCore()) {
      core.start();
      IllegalStateException e = assertThrows(IllegalStateException.class, core::start);
      assertTrue(e.getMessage().contains(core.name()), e.getMessage());
    }
  }

  @Test
  default void useAfterCloseIsRefused() throws InterruptedException {
    PrimeCore core = newCore();
    EventBlock<Integer> events = new EventBlock<>();
    Chain<Integer, Integer> unused = core.chain(x -> x);
    Chain<Integer, Integer> other = core.chain(x -> x);
    Source<Integer> source = core.source(events);
    Reader<Integer> reader = source.reader();
    core.start();
    core.close();
    assertThrows(CoreClosedException.class, () -> core.chain(x -> x));
    assertThrows(CoreClosedException.class, () -> core.chain("late", x -> x));
    assertThrows(CoreClosedException.class, () -> core.source(events));
    assertThrows(CoreClosedException.class, () -> core.link(unused, other));
    assertThrows(CoreClosedException.class, () -> core.link(source, core.chain(x -> x)));
    assertThrows(CoreClosedException.class, unused::toBlock);
    assertThrows(CoreClosedException.class, source::reader);
    assertThrows(CoreClosedException.class, reader::take);
    assertThrows(CoreClosedException.class, reader::poll);
    assertThrows(CoreClosedException.class, reader::drain);
    assertThrows(CoreClosedException.class, () -> reader.take(Duration.ofMillis(10)));
    events.publish(1); // the closed core no longer listens; publishing stays harmless
    assertNoThreadsLeft(core);
  }

  /**
   * A reader ends when its core closes, even with values left unread (the {@link Reader} methods'
   * {@code @throws CoreClosedException}; prime-test's {@code ReaderAssert.completes()} relies on
   * it): every read of a source's reader and of a chain's output reader then throws {@link
   * CoreClosedException} instead of handing out what was left.
   */
  @Test
  default void aClosedCoresReadersThrowThoughValuesWereLeftUnread() throws InterruptedException {
    PrimeCore core = newCore();
    EventBlock<Integer> events = new EventBlock<>();
    Source<Integer> source = core.source("numbers", events);
    Reader<Integer> numbers = source.reader();
    Reader<Integer> doubled = source.then(core.chain("double", (Integer x) -> 2 * x)).reader();
    core.start();
    for (int i = 1; i <= 3; i++) {
      events.publish(i);
    }
    assertEquals(1, numbers.take(patience()).orElseThrow());
    assertEquals(2, doubled.take(patience()).orElseThrow());
    assertEquals(4, doubled.take(patience()).orElseThrow());
    core.close();
    for (Reader<Integer> reader : List.of(numbers, doubled)) {
      assertThrows(CoreClosedException.class, reader::take);
      assertThrows(CoreClosedException.class, reader::poll);
      assertThrows(CoreClosedException.class, reader::drain);
      assertThrows(CoreClosedException.class, () -> reader.take(Duration.ofMillis(10)));
      assertThrows(CoreClosedException.class, () -> reader.take(Duration.ZERO));
    }
  }

  @Test
  default void nullArgumentsAreRefusedWithAMessage() {
    try (PrimeCore core = newCore()) {
      Chain<Integer, Integer> c = core.chain(x -> x);
      Source<Integer> s = core.source(new EventBlock<Integer>());
      List<Runnable> calls =
          List.of(
              () -> core.chain((dev.prime.Block<Integer, Integer>) null),
              () -> core.chain("n", null),
              () -> core.chain(null, (Integer x) -> x),
              () -> core.source((EventBlock<Integer>) null),
              () -> core.source("s", null),
              () -> core.link((Chain<Integer, Integer>) null, core.chain((Integer x) -> x)),
              () -> core.link(core.chain((Integer x) -> x), (Chain<Integer, Integer>) null),
              () -> core.link((Source<Integer>) null, core.chain((Integer x) -> x)),
              () -> core.link(s, (Chain<Integer, Integer>) null),
              () -> core.ifThenElse(null, core.chain((Integer x) -> x), core.chain((Integer x) -> x)),
              () -> core.forEach((Chain<Integer, Integer>) null),
              () -> core.fork(core.chain((Integer x) -> x), null),
              () -> core.guard(null, core.chain((Integer x) -> x), x -> x),
              () -> core.guard((Integer x) -> true, core.chain((Integer x) -> x), null),
              () -> core.isolate((Chain<Integer, Integer>) null),
              () -> core.syncCollector((Source<Integer>) null),
              () -> core.asyncCollector((Source<Integer>) null),
              () -> core.repeater(c, (dev.prime.RepeaterBlock<Integer, Integer, Void, Integer>) null));
      for (int i = 0; i < calls.size(); i++) {
        Runnable call = calls.get(i);
        NullPointerException e = assertThrows(NullPointerException.class, call::run, "call " + i);
        assertTrue(e.getMessage() != null && !e.getMessage().isBlank(), "call " + i + " has no message");
      }
    }
  }

  @Test
  default void invalidAndDuplicateNamesAreRefused() {
    try (PrimeCore core = newCore()) {
      core.chain("taken", x -> x);
      IllegalArgumentException dup =
          assertThrows(IllegalArgumentException.class, () -> core.chain("taken", x -> x));
      assertTrue(dup.getMessage().contains("taken"), dup.getMessage());
      assertThrows(IllegalArgumentException.class, () -> core.source("taken", new EventBlock<Integer>()));
      for (String bad : List.of("", "has space", "tab\t", "{brace}", "x".repeat(201))) {
        assertThrows(IllegalArgumentException.class, () -> core.chain(bad, x -> x), "name '" + bad + "'");
      }
    }
  }

  /**
   * {@link PrimeCore#chain(String, Block)}: a name is "1 to 200 characters, no whitespace or
   * braces", and the same for a generic service and a timer ("like a chain's"). Names at both
   * bounds and of every other kind of character are taken and work end to end: a chain of each
   * such name linked to a source of such a name computes, and its name is listed as a service. Each
   * name outside the rule (empty, 201 characters, a space, a tab, a line break, an em space, a
   * control character, an opening or a closing brace) is refused, by a chain, a generic service
   * and a timer alike, with an {@link IllegalArgumentException} that quotes the name and says
   * what a name may be.
   */
  @Test
  default void namesOfOneTo200CharactersWithoutWhitespaceOrBracesWorkAndOthersAreRefused()
      throws InterruptedException {
    String tag = Long.toString(System.nanoTime(), 36);
    List<String> good =
        List.of(
            "x",
            tag + "-" + "y".repeat(199 - tag.length()),
            "odd:name>with|pipes@at(round)[square]/slash*star?hash#100%&\"quote'" + tag,
            "caf\u00e9-\u03b8-\u2014-\ud83d\ude42-" + tag);
    assertEquals(200, good.get(1).length());
    try (PrimeCore core = newCore()) {
      List<Reader<Integer>> outs = new java.util.ArrayList<>();
      List<EventBlock<Integer>> feeds = new java.util.ArrayList<>();
      for (int i = 0; i < good.size(); i++) {
        EventBlock<Integer> events = new EventBlock<>();
        feeds.add(events);
        int plus = i + 1;
        String name = good.get(i);
        outs.add(
            core.source("s" + name.substring(1), events)
                .then(core.chain(name, (Integer x) -> x + plus))
                .reader());
      }
      assertTrue(core.serviceNames().containsAll(good), "the services: " + core.serviceNames());
      List<String> bad =
          List.of(
              "",
              "z".repeat(201),
              "has space",
              "tab\tbed",
              "line\nbreak",
              "em\u2003space",
              "no\u00a0break",
              "narrow\u202fno-break",
              "bell\u0007",
              "{open",
              "close}");
      List<String> wrong = new java.util.ArrayList<>();
      for (String name : bad) {
        java.util.Map<String, org.junit.jupiter.api.function.Executable> calls =
            new java.util.LinkedHashMap<>();
        calls.put("chain", () -> core.chain(name, (Integer x) -> x));
        calls.put("service", () -> core.service(name, () -> {}));
        calls.put("timer", () -> core.timer(name, Duration.ofHours(1)));
        for (java.util.Map.Entry<String, org.junit.jupiter.api.function.Executable> call :
            calls.entrySet()) {
          String what = "a " + call.getKey() + " named '" + name.replace("\n", "\\n") + "'";
          try {
            call.getValue().execute();
            wrong.add(what + " was accepted");
          } catch (IllegalArgumentException e) {
            String message = String.valueOf(e.getMessage());
            if (!message.contains("'" + name + "'") || !message.contains("1 to 200")) {
              wrong.add(what + ": " + message);
            }
          } catch (Throwable t) {
            wrong.add(what + " threw " + t);
          }
        }
      }
      assertEquals(List.of(), wrong, "each invalid name is refused, quoted, with the rule");
      core.start();
      for (int i = 0; i < good.size(); i++) {
        feeds.get(i).publish(10);
        assertEquals(10 + i + 1, takeOrFail(outs.get(i)), "the chain named '" + good.get(i) + "'");
      }
    }
  }

  /**
   * {@link CoreConfig.Builder}: each setting is checked where it is set, with a message naming
   * what is wrong: a name of 1 to 64 ASCII letters, digits, '.', '_' or '-', a source retention of at
   * least 1, a positive shutdown timeout, a zero or positive publish timeout, and no {@code null}
   * error handler, timeout or clock. A core takes the longest name of every allowed character
   * and runs under it.
   */
  @Test
  default void configurationIsValidated() throws InterruptedException {
    CoreConfig.Builder builder = CoreConfig.builder();
    for (String bad : List.of("", "has space", "slash/ed", "colon:", "x".repeat(65))) {
      IllegalArgumentException e =
          assertThrows(IllegalArgumentException.class, () -> builder.name(bad), "'" + bad + "'");
      assertTrue(
          e.getMessage().contains("'" + bad + "'") && e.getMessage().contains("1 to 64"),
          e.getMessage());
    }
    assertThrows(IllegalArgumentException.class, () -> builder.sourceRetention(0));
    for (Duration notPositive : List.of(Duration.ZERO, Duration.ofNanos(-1))) {
      IllegalArgumentException e =
          assertThrows(IllegalArgumentException.class, () -> builder.shutdownTimeout(notPositive));
      assertTrue(e.getMessage().contains("shutdownTimeout must be positive"), e.getMessage());
    }
    IllegalArgumentException negative =
        assertThrows(
            IllegalArgumentException.class, () -> builder.publishTimeout(Duration.ofNanos(-1)));
    assertTrue(negative.getMessage().contains("publishTimeout"), negative.getMessage());
    List<org.junit.jupiter.api.function.Executable> nulls =
        List.of(
            () -> builder.errorHandler(null),
            () -> builder.shutdownTimeout(null),
            () -> builder.publishTimeout(null),
            () -> builder.clock(null));
    for (org.junit.jupiter.api.function.Executable call : nulls) {
      NullPointerException e = assertThrows(NullPointerException.class, call);
      assertTrue(e.getMessage().contains("must not be null"), e.getMessage());
    }
    String unique = String.format("%08x", System.nanoTime() & 0xffffffffL);
    String longest = "Az09._-".repeat(8) + unique; // 64 characters, unique to this run
    try (PrimeCore core = newCore(builder.name(longest).build())) {
      assertEquals(longest, core.name());
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> out = core.source(events).then(core.chain((Integer x) -> x + 1)).reader();
      core.start();
      events.publish(1);
      assertEquals(2, takeOrFail(out));
    }
  }

  @Test
  default void serviceNamesListTheSourceLinks() {
    try (PrimeCore core = newCore()) {
      int before = core.serviceNames().size();
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source(events);
      core.link(source, core.chain(x -> x));
      core.link(source, core.chain(x -> x));
      assertEquals(before + 2, core.serviceNames().size(), "one service per linked chain");
    }
  }

  /**
   * Values published before {@code start()} wait in the services' inputs and are processed, in
   * order, once the core starts; an input filled before the start makes the next publish wait
   * {@code publishTimeout} and fail with {@code QueueFullException}, publishing nothing. A media
   * that refuses publishes before the start ({@link #publishesBeforeStartWait()} false) fails
   * each at once with {@code IllegalStateException}, and none reaches a service (architecture,
   * <i>Sources, readers and retention</i>, "Two cases to know", and <i>Lifecycle of a core</i>,
   * step 3).
   */
  @Test
  default void valuesPublishedBeforeStartWaitForTheServicesOrAreRefusedAtOnce()
      throws InterruptedException {
    int capacity = 3;
    CoreConfig config = CoreConfig.builder().publishTimeout(Duration.ofMillis(200)).build();
    try (PrimeCore core = newCoreWithServiceInputCapacity(config, capacity)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("early", events);
      Reader<Integer> doubled = core.link(source, core.chain("double", (Integer x) -> x * 2)).reader();
      Reader<Integer> odd = source.filter(x -> x % 2 == 1).reader();
      List<Integer> heard = new CopyOnWriteArrayList<>();
      CountDownLatch allHeard = new CountDownLatch(capacity + 2);
      source.listen(
          x -> {
            heard.add(x);
            allHeard.countDown();
          });
      if (publishesBeforeStartWait()) {
        for (int i = 1; i <= capacity; i++) {
          events.publish(i);
        }
        assertThrows(QueueFullException.class, () -> events.publish(99), "the inputs are full");
        core.start();
      } else {
        IllegalStateException refused =
            assertThrows(IllegalStateException.class, () -> events.publish(99));
        assertTrue(refused.getMessage().contains("start()"), refused.getMessage());
        core.start();
        for (int i = 1; i <= capacity; i++) {
          events.publish(i);
        }
      }
      assertEquals(List.of(2, 4, 6), takeOrFail(doubled, capacity));
      assertEquals(List.of(1, 3), takeOrFail(odd, 2));
      events.publish(4);
      events.publish(5);
      assertEquals(List.of(8, 10), takeOrFail(doubled, 2), "the refused 99 reached no chain");
      assertEquals(5, takeOrFail(odd), "the refused 99 reached no filter");
      assertTrue(allHeard.await(patience().toMillis(), TimeUnit.MILLISECONDS), "heard " + heard);
      assertEquals(List.of(1, 2, 3, 4, 5), heard, "the refused 99 reached no listener");
    }
  }

  /**
   * {@link PrimeCore}: "a closed core throws {@link CoreClosedException}", and {@link
   * PrimeCore#isStarted()} "stays true after {@link PrimeCore#close()}": on a started core that
   * was closed, every declaration of its public API (chains, sources, links, templates,
   * collectors, repeaters, combinators, timers, generic services, hooks, a new user of an
   * isolated chain, a source's {@code then}, {@code filter}, {@code flatMap}, {@code listen},
   * {@code withLatestFrom}, {@code sample} and readers) and {@code start()} throw {@link
   * CoreClosedException} naming the core (its message says to create a new one), never another
   * exception, and nothing is accepted.
   */
  @Test
  default void everyDeclarationOnAClosedCoreThrowsCoreClosedExceptionNamingIt() {
    PrimeCore core = newCore();
    EventBlock<Integer> events = new EventBlock<>();
    Source<Integer> source = core.source("numbers", events);
    Source<Integer> other = core.source("others", new EventBlock<Integer>());
    java.util.function.Supplier<Chain<Integer, Integer>> fresh =
        new java.util.function.Supplier<>() {
          private int made;

          @Override
          public Chain<Integer, Integer> get() {
            return core.chain("made-" + made++, (Integer x) -> x);
          }
        };
    List<Chain<Integer, Integer>> chains = new java.util.ArrayList<>();
    for (int i = 0; i < 40; i++) {
      chains.add(fresh.get());
    }
    java.util.Iterator<Chain<Integer, Integer>> given = chains.iterator();
    dev.prime.Isolated<Integer, Integer> isolated = core.isolate(given.next());
    core.start();
    core.close();
    assertTrue(core.isStarted(), "isStarted() stays true after close()");

    java.util.Map<String, org.junit.jupiter.api.function.Executable> calls =
        new java.util.LinkedHashMap<>();
    calls.put("start()", core::start);
    calls.put("chain(block)", () -> core.chain((Integer x) -> x));
    calls.put("chain(name, block)", () -> core.chain("late", (Integer x) -> x));
    calls.put("chain(name, pseudoname, block)", () -> core.chain("late", "Late", (Integer x) -> x));
    calls.put("source(events)", () -> core.source(new EventBlock<Integer>()));
    calls.put("source(name, events)", () -> core.source("late", new EventBlock<Integer>()));
    calls.put(
        "source(name, pseudoname, events)",
        () -> core.source("late", "Late", new EventBlock<Integer>()));
    calls.put("link(chain, chain)", () -> core.link(given.next(), given.next()));
    calls.put("link(source, chain)", () -> core.link(source, given.next()));
    calls.put("chain.then(chain)", () -> given.next().then(given.next()));
    calls.put("chain.then(block)", () -> given.next().then((Integer x) -> x));
    calls.put("chain.toBlock()", () -> given.next().toBlock());
    calls.put("source.then(chain)", () -> source.then(given.next()));
    calls.put("source.then(block)", () -> source.then((Integer x) -> x));
    calls.put("source.filter", () -> source.filter(x -> true));
    calls.put("source.flatMap", () -> source.flatMap(x -> List.of(x)));
    calls.put("source.listen", () -> source.listen(x -> {}));
    calls.put("source.withLatestFrom", () -> source.withLatestFrom(other));
    calls.put("source.sample", () -> source.sample(Duration.ofSeconds(1)));
    calls.put("source.reader()", source::reader);
    calls.put("source.conflatedReader()", source::conflatedReader);
    calls.put(
        "ifThenElse", () -> core.ifThenElse((Integer x) -> x > 0, given.next(), given.next()));
    calls.put("forEach", () -> core.forEach(given.next()));
    calls.put("union of 2", () -> core.union(given.next(), given.next()));
    calls.put("union of 3", () -> core.union(given.next(), given.next(), given.next()));
    calls.put("fork", () -> core.fork(given.next(), new EventBlock<Integer>()));
    calls.put("guard", () -> core.guard((Integer x) -> true, given.next(), (Integer x) -> x));
    calls.put("isolate", () -> core.isolate(given.next()));
    calls.put("isolated.newUser()", isolated::newUser);
    calls.put("syncCollector", () -> core.syncCollector(source));
    calls.put("asyncCollector", () -> core.asyncCollector(source));
    calls.put(
        "repeater(inner, decide)",
        () -> core.repeater(given.next(), (input, output, collected) -> dev.prime.Repeat.stop(output)));
    calls.put(
        "repeater(inner, source, decide)",
        () ->
            core.repeater(
                given.next(), source, (input, output, collected) -> dev.prime.Repeat.stop(output)));
    calls.put("combineLatest", () -> core.combineLatest(source, other));
    calls.put("zip", () -> core.zip(source, other));
    calls.put("merge", () -> core.merge(source, other));
    calls.put("timer", () -> core.timer("late-timer", Duration.ofSeconds(1)));
    calls.put("service", () -> core.service("late-service", () -> {}));
    calls.put("whenRunning", () -> core.whenRunning("late-hook", () -> {}, () -> {}));

    List<String> wrong = new java.util.ArrayList<>();
    for (java.util.Map.Entry<String, org.junit.jupiter.api.function.Executable> call :
        calls.entrySet()) {
      try {
        call.getValue().execute();
        wrong.add(call.getKey() + " was accepted");
      } catch (CoreClosedException e) {
        if (e.getMessage() == null || !e.getMessage().contains("'" + core.name() + "'")) {
          wrong.add(call.getKey() + " threw a CoreClosedException saying " + e.getMessage());
        }
      } catch (Throwable t) {
        wrong.add(call.getKey() + " threw " + t);
      }
    }
    assertEquals(List.of(), wrong, "every declaration on a closed core throws CoreClosedException");
    assertTrue(core.isStarted(), "isStarted() stays true after the refused start()");
    assertNoThreadsLeft(core);
  }

  /**
   * A chain or source of a closed core is refused at the declaration that takes it, with {@code
   * CoreClosedException} naming that core, and the refused declaration consumes nothing
   * (architecture, <i>What every media keeps</i>, "Misuse").
   */
  @Test
  default void aChainOrSourceOfAClosedCoreIsRefusedAndTheRefusalConsumesNothing()
      throws InterruptedException {
    PrimeCore closed = newCore();
    Chain<Integer, Integer> stale = closed.chain("stale", x -> x);
    Source<Integer> old = closed.source("old", new EventBlock<Integer>());
    closed.close();
    try (PrimeCore core = newCore()) {
      Chain<Integer, Integer> fresh = core.chain("fresh", (Integer x) -> x + 1);
      CoreClosedException refused =
          assertThrows(CoreClosedException.class, () -> core.link(fresh, stale));
      assertTrue(refused.getMessage().contains(closed.name()), refused.getMessage());
      Chain<Integer, Integer> next = core.chain("next", (Integer x) -> x * 10);
      refused = assertThrows(CoreClosedException.class, () -> core.link(old, next));
      assertTrue(refused.getMessage().contains(closed.name()), refused.getMessage());
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> out = core.link(core.source("live", events), next).reader();
      Block<Integer, Integer> block = fresh.toBlock();
      core.start();
      assertEquals(2, block.process(1), "the refused link left its own chain usable");
      events.publish(3);
      assertEquals(30, takeOrFail(out), "the refused source link left its chain usable");
    }
  }

  /**
   * {@link CoreConfig#shutdownTimeout()}: "how long {@link PrimeCore#close()} waits for each group
   * of services to stop". A service whose block ignores interrupts does not hold {@code close()}
   * up: it returns within a few shutdown timeouts (under 5 s here, a quarter of the patience the
   * block would hold it), the core is closed, and a WARN line naming the core ({@code core
   * '<name>': ... still running ...}) says what it left running; a thread it left is a daemon,
   * which cannot keep the JVM alive. The block is let go afterwards, and its thread then ends.
   */
  @Test
  default void closeReturnsWithinTheShutdownTimeoutWhenABlockIgnoresInterrupts()
      throws InterruptedException {
    Duration shutdown = Duration.ofMillis(200);
    CountDownLatch inside = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    PrimeCore core = newCore(CoreConfig.builder().shutdownTimeout(shutdown).build());
    CapturedStderr err = new CapturedStderr();
    try {
      holdADeafBlock(core, new EventBlock<>(), "deaf", inside, release);
      long began = System.nanoTime();
      core.close();
      Duration took = Duration.ofNanos(System.nanoTime() - began);
      assertTrue(core.isClosed());
      assertTrue(
          took.compareTo(shutdown.multipliedBy(5).plusSeconds(4)) < 0,
          "close() waited " + took + " with a shutdown timeout of " + shutdown);
      String prefix = "prime-" + core.name() + "-";
      for (Thread left : Thread.getAllStackTraces().keySet()) {
        if (left.isAlive() && left.getName().startsWith(prefix)) {
          assertTrue(left.isDaemon(), left.getName() + " left running cannot keep the JVM alive");
        }
      }
      String named = "core '" + core.name() + "'";
      assertTrue(
          err.lines().stream().anyMatch(l -> l.contains(named) && l.contains("still running")),
          "close() said that a service of " + named + " is still running: " + err.lines());
    } finally {
      release.countDown();
      err.close();
    }
    awaitNoThreadsLeft(core);
  }
  /**
   * {@code close()} racing with work on other threads ends each cleanly, within the kit's
   * patience: publishers, readers waiting in {@code take()} and callers of a chain's block run in
   * loops while two threads close the core at once. A publish returns (after the close it
   * publishes nothing) or throws {@link CoreClosedException}; a take returns a value or throws
   * {@link CoreClosedException}, and every take ends with it; a call returns the block's value or
   * throws {@link CoreClosedException}; nothing hangs, nothing else is thrown, both closes return,
   * and the core leaves no thread. A call after {@code close()} of a chain of plain blocks returns
   * the block's value where blocks run on the caller's thread (the in-memory media: the chain's
   * block is a composed function that needs nothing of the core) and throws {@link
   * CoreClosedException} where chains are services (architecture, <i>Lifecycle of a core</i>).
   */
  @Test
  default void closeRacingWithPublishersTakersAndCallersEndsEachCleanly() throws Exception {
    PrimeCore core = newCore();
    EventBlock<Integer> events = new EventBlock<>();
    Source<Integer> doubled =
        core.source("racing", events).then(core.chain("racing-double", (Integer x) -> x * 2));
    Block<Integer, Integer> triple = core.chain("racing-triple", (Integer x) -> x * 3).toBlock();
    List<Reader<Integer>> readers = List.of(doubled.reader(), doubled.reader());
    core.start();
    List<Throwable> unexpected = new CopyOnWriteArrayList<>();
    List<String> endings = new CopyOnWriteArrayList<>();
    CountDownLatch working = new CountDownLatch(6);
    List<Thread> workers = new java.util.ArrayList<>();
    for (int p = 0; p < 2; p++) {
      workers.add(
          worker(
              "publisher",
              working,
              unexpected,
              endings,
              () -> {
                for (int i = 0; !core.isClosed(); i++) {
                  events.publish(i);
                }
              }));
      workers.add(
          worker(
              "caller",
              working,
              unexpected,
              endings,
              () -> {
                for (int i = 0; !core.isClosed(); i++) {
                  if (triple.process(i) != i * 3) {
                    throw new AssertionError("a call racing close() returned a wrong value");
                  }
                }
              }));
    }
    for (Reader<Integer> reader : readers) {
      workers.add(
          worker(
              "taker",
              working,
              unexpected,
              endings,
              () -> {
                while (true) {
                  if (reader.take() % 2 != 0) {
                    throw new AssertionError("a take racing close() returned a wrong value");
                  }
                }
              }));
    }
    assertTrue(working.await(patience().toMillis(), TimeUnit.MILLISECONDS), "the workers began");
    CountDownLatch closed = new CountDownLatch(2);
    for (int c = 0; c < 2; c++) {
      Thread closer =
          new Thread(
              () -> {
                try {
                  core.close();
                } catch (Throwable t) {
                  unexpected.add(t);
                } finally {
                  closed.countDown();
                }
              },
              "kit-closer-" + c);
      closer.setDaemon(true);
      closer.start();
    }
    assertTrue(closed.await(patience().toMillis(), TimeUnit.MILLISECONDS), "both closes returned");
    for (Thread worker : workers) {
      worker.join(patience().toMillis());
      assertFalse(worker.isAlive(), worker.getName() + " still runs after close()");
    }
    assertEquals(List.of(), unexpected, "only CoreClosedException may end a racing call");
    assertEquals(2, endings.stream().filter(e -> e.startsWith("taker")).count(), "endings " + endings);
    if (blocksRunOnTheCallersThread()) {
      assertEquals(15, triple.process(5), "a plain chain's block needs nothing of the closed core");
    } else {
      assertThrows(CoreClosedException.class, () -> triple.process(5), "a call after close()");
    }
    assertNoThreadsLeft(core);
  }

  /**
   * A daemon thread that counts {@code working} down and runs {@code work}: an ending by {@link
   * CoreClosedException} is noted in {@code endings}, any other throwable in {@code unexpected}.
   */
  private static Thread worker(
      String name,
      CountDownLatch working,
      List<Throwable> unexpected,
      List<String> endings,
      InterruptConformance.Callable work) {
    Thread thread =
        new Thread(
            () -> {
              working.countDown();
              try {
                work.run();
              } catch (CoreClosedException e) {
                endings.add(name);
              } catch (Throwable t) {
                unexpected.add(t);
              }
            },
            "kit-racing-" + name);
    thread.setDaemon(true);
    thread.start();
    return thread;
  }
  /**
   * A {@code close()} that finds another {@code close()} under way on another thread waits until
   * that one has finished ({@link PrimeCore#close()}), so a shutdown hook that closes a core the
   * program is closing does not let the JVM exit half-way: here the first close is held for its
   * whole shutdown timeout by a block that ignores interrupts, and the second returns only after
   * that; both leave no thread once the block returns.
   */
  @Test
  default void aCloseThatFindsAnotherUnderWayWaitsForItToFinish() throws InterruptedException {
    Duration shutdown = Duration.ofSeconds(2);
    CountDownLatch inside = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    CountDownLatch firstReturned = new CountDownLatch(1);
    PrimeCore core = newCore(CoreConfig.builder().shutdownTimeout(shutdown).build());
    try {
      holdADeafBlock(core, new EventBlock<>(), "holding", inside, release);
      long firstBegan = System.nanoTime();
      Thread first =
          new Thread(
              () -> {
                core.close();
                firstReturned.countDown();
              },
              "kit-first-close");
      first.setDaemon(true);
      first.start();
      long deadline = System.nanoTime() + patience().toNanos();
      while (!core.isClosed() && System.nanoTime() < deadline) {
        firstReturned.await(1, TimeUnit.MILLISECONDS); // a bounded pause until it began
      }
      assertTrue(core.isClosed(), "the first close() began");
      core.close();
      Duration sinceFirst = Duration.ofNanos(System.nanoTime() - firstBegan);
      // the first close's timed join counts whole milliseconds, so it may end just under the timeout
      assertTrue(
          sinceFirst.compareTo(shutdown.minus(JOIN_GRANULARITY)) >= 0,
          "the second close() returned only after the first had waited out its shutdown timeout"
              + " of "
              + shutdown
              + ", but returned "
              + sinceFirst
              + " after the first began");
      assertTrue(
          firstReturned.await(patience().toMillis(), TimeUnit.MILLISECONDS), "the first returned");
    } finally {
      release.countDown();
    }
    awaitNoThreadsLeft(core);
  }

  /**
   * {@link PrimeCore#close()}: a {@code close()} that finds another under way waits for it, but
   * "an interrupt ends its wait and stays set". While the first close is held for its shutdown
   * timeout of 10 s by a block that ignores interrupts, a second {@code close()} on an interrupted
   * thread returns within a second, throwing nothing, with the thread's interrupt flag still set.
   */
  @Test
  default void anInterruptEndsTheWaitOfASecondCloseAndStaysSet() throws InterruptedException {
    CountDownLatch inside = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    PrimeCore core =
        newCore(CoreConfig.builder().shutdownTimeout(Duration.ofSeconds(10)).build());
    Thread first = null;
    try {
      holdADeafBlock(core, new EventBlock<>(), "holding", inside, release);
      first = new Thread(core::close, "kit-first-close");
      first.setDaemon(true);
      first.start();
      long deadline = System.nanoTime() + patience().toNanos();
      while (!core.isClosed() && System.nanoTime() < deadline) {
        first.join(1); // a bounded pause until the first close() began
      }
      assertTrue(core.isClosed(), "the first close() began");
      Thread.currentThread().interrupt();
      long began = System.nanoTime();
      core.close();
      Duration took = Duration.ofNanos(System.nanoTime() - began);
      assertTrue(Thread.interrupted(), "the interrupt flag stays set");
      assertTrue(took.compareTo(Duration.ofSeconds(1)) < 0, "the interrupt ended the wait: " + took);
      assertTrue(first.isAlive(), "the first close() is still under way");
    } finally {
      Thread.interrupted();
      release.countDown();
      if (first != null) {
        first.join(patience().toMillis());
      }
    }
    awaitNoThreadsLeft(core);
  }

  /**
   * A {@code close()} called by a block on a service's thread while another {@code close()} is
   * under way returns at once ({@link PrimeCore#close()}): the close under way is waiting for that
   * very thread, so waiting for it in turn would hold both up; the first close then returns well
   * within its shutdown timeout.
   */
  @Test
  default void aCloseFromAServiceWhileAnotherIsUnderWayReturnsAtOnce()
      throws InterruptedException {
    Duration shutdown = Duration.ofSeconds(10);
    CountDownLatch inside = new CountDownLatch(1);
    AtomicReference<Duration> blockClose = new AtomicReference<>();
    PrimeCore core = newCore(CoreConfig.builder().shutdownTimeout(shutdown).build());
    EventBlock<Integer> events = new EventBlock<>();
    core.source(events)
        .then(
            core.chain(
                "closing-too",
                (Integer x) -> {
                  inside.countDown();
                  long deadline = System.nanoTime() + patience().toNanos();
                  CountDownLatch never = new CountDownLatch(1);
                  while (!core.isClosed() && System.nanoTime() < deadline) {
                    try {
                      never.await(1, TimeUnit.MILLISECONDS); // a bounded pause until close() began
                    } catch (InterruptedException e) {
                      break; // the close under way interrupts the service
                    }
                  }
                  long began = System.nanoTime();
                  core.close();
                  blockClose.set(Duration.ofNanos(System.nanoTime() - began));
                  return x;
                }));
    core.start();
    events.publish(1);
    assertTrue(inside.await(patience().toMillis(), TimeUnit.MILLISECONDS));
    long began = System.nanoTime();
    core.close();
    Duration took = Duration.ofNanos(System.nanoTime() - began);
    assertTrue(
        took.compareTo(Duration.ofSeconds(5)) < 0,
        "the first close() did not wait out its shutdown timeout: " + took);
    assertNotNull(blockClose.get(), "the block's close() returned before the first close did");
    assertTrue(
        blockClose.get().compareTo(Duration.ofSeconds(1)) < 0,
        "the block's close() returned at once: " + blockClose.get());
    assertNoThreadsLeft(core);
  }

  /**
   * The longest timeouts a {@link Duration} holds are timeouts like any other: {@link
   * CoreConfig.Builder#shutdownTimeout} takes any positive one and {@link
   * CoreConfig.Builder#publishTimeout} any zero or positive one, so a program that means "as long
   * as it takes" may give {@code Duration.ofSeconds(Long.MAX_VALUE)}. A publish then goes through,
   * {@code close()} stops every service ({@link PrimeCore}, "What every media guarantees"), and a
   * second {@code close()} that finds the first under way waits for it ({@link PrimeCore#close()});
   * none of them throws.
   */
  @Test
  default void theLongestTimeoutsADurationHoldsWorkLikeAnyOther() throws InterruptedException {
    Duration longest = Duration.ofSeconds(Long.MAX_VALUE, 999_999_999);
    CountDownLatch inside = new CountDownLatch(1);
    CountDownLatch release = new CountDownLatch(1);
    List<Throwable> failures = new CopyOnWriteArrayList<>();
    PrimeCore core =
        newCore(CoreConfig.builder().shutdownTimeout(longest).publishTimeout(longest).build());
    Thread first = null;
    Thread second = null;
    try {
      EventBlock<Integer> events = new EventBlock<>();
      Reader<Integer> out = core.source(events).then(core.chain((Integer x) -> x + 1)).reader();
      holdADeafBlock(core, events, "holding", inside, release);
      assertEquals(2, takeOrFail(out), "the publish went through");
      first = closer(core, "kit-longest-first-close", failures);
      long deadline = System.nanoTime() + patience().toNanos();
      while (!core.isClosed() && first.isAlive() && System.nanoTime() < deadline) {
        first.join(1); // a bounded pause until the first close() began
      }
      assertTrue(core.isClosed(), "the first close() began");
      second = closer(core, "kit-longest-second-close", failures);
      while (second.isAlive()
          && second.getState() != Thread.State.WAITING
          && second.getState() != Thread.State.TIMED_WAITING
          && System.nanoTime() < deadline) {
        second.join(1); // a bounded pause until the second close() waits or ended
      }
      assertTrue(first.isAlive(), "the first close() waits for the block that ignores interrupts");
    } finally {
      release.countDown();
      if (first == null) {
        closer(core, "kit-longest-cleanup-close", failures).join(patience().toMillis());
      }
      for (Thread closing : new Thread[] {first, second}) {
        if (closing != null) {
          closing.join(patience().toMillis());
          assertFalse(closing.isAlive(), closing.getName() + " returned");
        }
      }
    }
    assertEquals(List.of(), failures, "what the close() calls threw");
    assertTrue(core.isClosed());
    awaitNoThreadsLeft(core);
  }

  /** A daemon thread that closes {@code core} and notes in {@code failures} what it threw. */
  private static Thread closer(PrimeCore core, String name, List<Throwable> failures) {
    Thread thread =
        new Thread(
            () -> {
              try {
                core.close();
              } catch (Throwable t) {
                failures.add(t);
              }
            },
            name);
    thread.setDaemon(true);
    thread.start();
    return thread;
  }

  /**
   * Declarations racing {@code close()} end cleanly: declaring is "allowed at any time before
   * {@link PrimeCore#close()}" and "a closed core throws {@link CoreClosedException}" ({@link
   * PrimeCore}, "Threading" and "What every media guarantees"). Here a thread declares sources,
   * links, filters, listeners and generic services on a started core in a loop while the core
   * closes: each declaration either succeeds or throws {@link CoreClosedException}, nothing else,
   * and the core leaves no thread, in every one of a number of rounds.
   */
  @Test
  default void declarationsRacingCloseSucceedOrThrowCoreClosedException() throws Exception {
    for (int round = 0; round < 100; round++) {
      PrimeCore core = newCore();
      core.start();
      CountDownLatch declaring = new CountDownLatch(1);
      AtomicReference<Throwable> ending = new AtomicReference<>();
      Thread declarer =
          new Thread(
              () -> {
                try {
                  for (int i = 0; i < 10_000 && !core.isClosed(); i++) {
                    EventBlock<Integer> events = new EventBlock<>();
                    Source<Integer> source = core.source("racing-" + i, events);
                    declaring.countDown();
                    source.then(core.chain("racing-chain-" + i, (Integer x) -> x));
                    source.filter(x -> x > 0);
                    source.listen(x -> {});
                    core.service("racing-service-" + i, () -> Thread.sleep(1_000));
                  }
                } catch (Throwable t) {
                  ending.set(t);
                } finally {
                  declaring.countDown();
                }
              },
              "kit-racing-declarer");
      declarer.setDaemon(true);
      declarer.start();
      assertTrue(declaring.await(patience().toMillis(), TimeUnit.MILLISECONDS), "declaring began");
      core.close();
      declarer.join(patience().toMillis());
      assertFalse(declarer.isAlive(), "the declarer ended after close()");
      Throwable thrown = ending.get();
      if (thrown != null && !(thrown instanceof CoreClosedException)) {
        throw new AssertionError(
            "round " + round + ": a declaration racing close() threw " + thrown, thrown);
      }
      awaitNoThreadsLeft(core);
    }
  }

  /**
   * Links to a source of {@code events}, on {@code core} (not started), a chain whose block counts
   * {@code inside} down, then ignores interrupts until {@code release} opens (or the kit's patience
   * runs out); starts the core, publishes 1 and returns once the block holds it: a {@code
   * close()} now waits up to its shutdown timeout.
   */
  private void holdADeafBlock(
      PrimeCore core,
      EventBlock<Integer> events,
      String name,
      CountDownLatch inside,
      CountDownLatch release)
      throws InterruptedException {
    core.source(events).then(deafChain(core, name, inside, release));
    core.start();
    events.publish(1);
    assertTrue(inside.await(patience().toMillis(), TimeUnit.MILLISECONDS), "the block holds a value");
  }

  /** The chain of {@link #holdADeafBlock}. */
  private Chain<Integer, Integer> deafChain(
      PrimeCore core, String name, CountDownLatch inside, CountDownLatch release) {
    return core.chain(
        name,
        (Integer x) -> {
          inside.countDown();
          long deadline = System.nanoTime() + patience().toNanos();
          while (release.getCount() > 0 && System.nanoTime() < deadline) {
            try {
              release.await(10, TimeUnit.MILLISECONDS);
            } catch (InterruptedException ignored) {
              // deaf on purpose
            }
          }
          return x;
        });
  }

  /**
   * {@link CoreConfig#name()}: "the core's name, used in thread names and log lines, or {@code
   * null} for a generated one ({@code liberty-1}, ...)". A core given a name has it; two cores
   * given none get distinct names {@code <media>-N} of the same media; and the thread a service
   * runs its block on carries the core's name.
   */
  @Test
  default void aCoreHasTheNameItsConfigGivesOrAGeneratedOneAndItsServiceThreadsCarryIt()
      throws InterruptedException {
    String given = "kit-named-" + Long.toString(System.nanoTime(), 36);
    try (PrimeCore named = newCore(CoreConfig.builder().name(given).build());
        PrimeCore first = newCore();
        PrimeCore second = newCore()) {
      assertEquals(given, named.name());
      for (PrimeCore core : List.of(first, second)) {
        assertTrue(core.name().matches("[a-z]+-[0-9]+"), "a generated name <media>-N: " + core.name());
      }
      assertNotEquals(first.name(), second.name());
      assertEquals(
          first.name().substring(0, first.name().lastIndexOf('-')),
          second.name().substring(0, second.name().lastIndexOf('-')),
          "one media, one prefix");
      for (PrimeCore core : List.of(named, first)) {
        AtomicReference<String> ranOn = new AtomicReference<>();
        EventBlock<Integer> events = new EventBlock<>();
        Reader<Integer> out =
            core.link(
                    core.source(events),
                    core.chain(
                        (Integer x) -> {
                          ranOn.set(Thread.currentThread().getName());
                          return x;
                        }))
                .reader();
        core.start();
        events.publish(1);
        assertEquals(1, takeOrFail(out));
        assertTrue(
            ranOn.get().contains(core.name()),
            "the service's thread carries the core's name '" + core.name() + "': " + ranOn.get());
      }
    }
  }

  /**
   * {@link CoreClosedException}: "A core, or one of its chains, sources or readers, was used after
   * {@link PrimeCore#close()}". Whichever of them is used, the exception names the closed core, so
   * a program with several cores can tell which one it used too late.
   */
  @Test
  default void everyCoreClosedExceptionNamesTheClosedCore() throws InterruptedException {
    PrimeCore core = newCore();
    EventBlock<Integer> events = new EventBlock<>();
    Chain<Integer, Integer> unused = core.chain(x -> x);
    Source<Integer> source = core.source(events);
    Reader<Integer> reader = source.reader();
    core.start();
    core.close();
    List<org.junit.jupiter.api.function.Executable> uses =
        List.of(
            core::start,
            () -> core.chain(x -> x),
            () -> core.source(new EventBlock<Integer>()),
            () -> core.whenRunning("late", () -> {}, () -> {}),
            unused::toBlock,
            source::reader,
            reader::take,
            reader::poll,
            reader::drain,
            () -> reader.take(Duration.ofMillis(10)));
    for (org.junit.jupiter.api.function.Executable use : uses) {
      CoreClosedException e = assertThrows(CoreClosedException.class, use);
      assertTrue(
          e.getMessage() != null && e.getMessage().contains("'" + core.name() + "'"),
          "names the closed core '" + core.name() + "': " + e.getMessage());
    }
  }
}

package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.GenericService;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Source;
import java.time.Duration;
import java.util.ArrayList;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.UUID;
import java.util.function.Consumer;
import java.util.function.Predicate;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.function.Executable;

/**
 * Misuse of the declaration API beyond the calls {@link LifecycleConformance} checks, and the
 * start line's bound (architecture, <i>Errors</i>, "Misuse"; <i>Values</i>, the logging list).
 */
public interface MisuseConformance extends LoggingConformance {

  /**
   * "A {@code null} block is a {@code NullPointerException} naming the argument", and "a call that
   * is refused changes nothing" (architecture, <i>Errors</i>, "Misuse"), for every declaration
   * that takes a chain, a source, a block, a name or a period: each {@code null} is refused at the
   * call with a {@link NullPointerException} whose message says what must not be null, never
   * another exception, and the chains and sources given with it stay usable (a chain given next to
   * the {@code null} still computes through {@code toBlock()}; a name given next to it stays free).
   */
  @Test
  default void everyNullArgumentIsRefusedNamingItAndConsumesNothing() throws InterruptedException {
    Map<String, Executable> calls = new LinkedHashMap<>();
    List<Chain<Integer, Integer>> givenChains = new ArrayList<>();
    List<String> givenNames = new ArrayList<>();
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("numbers", events);
      Source<Integer> other = core.source("others", new EventBlock<Integer>());
      java.util.function.Supplier<Chain<Integer, Integer>> given =
          () -> {
            Chain<Integer, Integer> chain = core.chain((Integer x) -> x + 1);
            givenChains.add(chain);
            return chain;
          };
      calls.put("chain.then((Chain) null)", () -> given.get().then((Chain<Integer, Integer>) null));
      calls.put("chain.then((Block) null)", () -> given.get().then((Block<Integer, Integer>) null));
      calls.put("source.then((Chain) null)", () -> source.then((Chain<Integer, Integer>) null));
      calls.put("source.then((Block) null)", () -> source.then((Block<Integer, Integer>) null));
      calls.put("source.filter(null)", () -> source.filter((Predicate<Integer>) null));
      calls.put("source.flatMap(null)", () -> source.flatMap(null));
      calls.put("source.listen(null)", () -> source.listen((Consumer<Integer>) null));
      calls.put("source.withLatestFrom(null)", () -> source.withLatestFrom(null));
      calls.put("source.sample(null)", () -> source.sample(null));
      calls.put("union(chain, null)", () -> core.union(given.get(), (Chain<Integer, Integer>) null));
      calls.put("union(null, chain)", () -> core.union((Chain<Integer, Integer>) null, given.get()));
      calls.put(
          "union(chain, chain, null)",
          () -> core.union(given.get(), given.get(), (Chain<Integer, Integer>) null));
      calls.put(
          "union(chain, chain, chain, null)",
          () -> core.union(given.get(), given.get(), given.get(), (Chain<Integer, Integer>) null));
      calls.put(
          "union(chain, chain, chain, chain, null)",
          () ->
              core.union(
                  given.get(), given.get(), given.get(), given.get(), (Chain<Integer, Integer>) null));
      calls.put(
          "ifThenElse(condition, null, chain)",
          () -> core.ifThenElse((Integer x) -> x > 0, null, given.get()));
      calls.put(
          "ifThenElse(condition, chain, null)",
          () -> core.ifThenElse((Integer x) -> x > 0, given.get(), null));
      calls.put(
          "guard(pass, null, substitute)",
          () -> core.guard((Integer x) -> true, (Chain<Integer, Integer>) null, (Integer x) -> x));
      calls.put("fork(null, events)", () -> core.fork(null, new EventBlock<Integer>()));
      calls.put("repeater(null, decide)", () -> core.repeater(null, (input, output, collected) -> null));
      calls.put(
          "repeater(chain, null source, decide)",
          () -> core.repeater(given.get(), (Source<Integer>) null, (input, output, collected) -> null));
      calls.put("combineLatest(source, null)", () -> core.combineLatest(source, (Source<Integer>) null));
      calls.put("combineLatest(null, source)", () -> core.combineLatest((Source<Integer>) null, source));
      calls.put("zip(source, null)", () -> core.zip(source, (Source<Integer>) null));
      calls.put("zip(source, other, null)", () -> core.zip(source, other, (Source<Integer>) null));
      calls.put("merge(source, null)", () -> core.merge(source, null));
      calls.put("merge((Source[]) null)", () -> core.merge((Source<Integer>[]) null));
      calls.put("timer(null, period)", () -> core.timer(null, Duration.ofSeconds(1)));
      givenNames.add("free-timer");
      calls.put("timer(name, null)", () -> core.timer("free-timer", null));
      calls.put("service(null, service)", () -> core.service(null, () -> {}));
      givenNames.add("free-service");
      calls.put("service(name, null)", () -> core.service("free-service", (GenericService) null));
      calls.put("whenRunning(null, onStart, onClose)", () -> core.whenRunning(null, () -> {}, () -> {}));
      calls.put("whenRunning(name, null, onClose)", () -> core.whenRunning("hook", null, () -> {}));
      calls.put("whenRunning(name, onStart, null)", () -> core.whenRunning("hook", () -> {}, null));
      givenNames.add("free-chain");
      calls.put("chain(name, pseudoname, null)", () -> core.chain("free-chain", "Free", null));
      calls.put("chain(null, pseudoname, block)", () -> core.chain(null, "Free", (Integer x) -> x));
      givenNames.add("free-source");
      calls.put("source(name, pseudoname, null)", () -> core.source("free-source", "Free", null));
      givenNames.add("free-chain-2");
      calls.put(
          "chain(name, null, block)", () -> core.chain("free-chain-2", null, (Integer x) -> x));
      givenNames.add("free-source-2");
      calls.put(
          "source(name, null, events)",
          () -> core.source("free-source-2", null, new EventBlock<Integer>()));
      calls.put(
          "source(null, pseudoname, events)",
          () -> core.source(null, "Free", new EventBlock<Integer>()));
      calls.put(
          "repeater(chain, source, null)",
          () ->
              core.repeater(
                  given.get(), source, (dev.prime.RepeaterBlock<Integer, Integer, Integer, Integer>) null));

      List<String> wrong = new ArrayList<>();
      for (Map.Entry<String, Executable> call : calls.entrySet()) {
        try {
          call.getValue().execute();
          wrong.add(call.getKey() + " was accepted");
        } catch (NullPointerException e) {
          String message = e.getMessage();
          if (message == null || !message.contains("null")) {
            wrong.add(call.getKey() + " threw a NullPointerException saying " + message);
          }
        } catch (Throwable t) {
          wrong.add(call.getKey() + " threw " + t);
        }
      }
      assertEquals(List.of(), wrong, "each null is refused with a NullPointerException naming it");

      Reader<Integer> numbers = source.reader();
      Reader<Integer> plusOne = source.then(core.chain("plus-one", (Integer x) -> x + 1)).reader();
      for (String name : givenNames) {
        core.chain(name, (Integer x) -> x); // each name a refused call was given is still free
      }
      core.start();
      for (int i = 0; i < givenChains.size(); i++) {
        assertEquals(
            8, givenChains.get(i).toBlock().process(7), "chain " + i + " given to a refused call");
      }
      events.publish(41);
      assertEquals(41, takeOrFail(numbers), "the source of refused calls still carries values");
      assertEquals(42, takeOrFail(plusOne));
    }
  }

  /**
   * "A {@code null} ... is a {@code NullPointerException} naming the argument" (architecture,
   * <i>Errors</i>, "Misuse"), for what reads and feeds a source: the event block a source is made
   * of, a source given to a link or a collector, a value published, a reader's (and a conflated
   * reader's) timeout. Each is refused at the call, on every media the same way: a {@link
   * NullPointerException} whose message names the parameter ({@code events}, {@code source},
   * {@code chain}, {@code timeout}) and says it must not be {@code null} (or, for a value, what to
   * publish instead) — never an exception the JVM or a language runtime makes up.
   */
  @Test
  default void everyNullGivenToASourceOrAReaderIsRefusedNamingTheParameter()
      throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("fed", events);
      Reader<Integer> reader = source.reader();
      Reader<Integer> conflated = source.conflatedReader();
      Map<String, Map.Entry<String, Executable>> calls = new LinkedHashMap<>();
      calls.put("source(null)", Map.entry("events", () -> core.source((EventBlock<Integer>) null)));
      calls.put(
          "source(name, null)", Map.entry("events", () -> core.source("unfed", (EventBlock<Integer>) null)));
      calls.put(
          "link(null, chain)",
          Map.entry("source", () -> core.link((Source<Integer>) null, core.chain((Integer x) -> x))));
      calls.put(
          "link(source, null)",
          Map.entry("chain", () -> core.link(source, (Chain<Integer, Integer>) null)));
      calls.put("syncCollector(null)", Map.entry("source", () -> core.syncCollector(null)));
      calls.put("asyncCollector(null)", Map.entry("source", () -> core.asyncCollector(null)));
      core.start();
      calls.put("events.publish(null)", Map.entry("Optional", () -> events.publish(null)));
      calls.put("reader.take(null)", Map.entry("timeout", () -> reader.take(null)));
      calls.put("conflatedReader.take(null)", Map.entry("timeout", () -> conflated.take(null)));
      List<String> wrong = new ArrayList<>();
      for (Map.Entry<String, Map.Entry<String, Executable>> call : calls.entrySet()) {
        String named = call.getValue().getKey();
        try {
          call.getValue().getValue().execute();
          wrong.add(call.getKey() + " was accepted");
        } catch (NullPointerException e) {
          String message = e.getMessage();
          if (message == null
              || !message.contains(named)
              || !message.contains("null")
              || message.contains("Parameter specified as non-null")
              || message.contains("Cannot invoke")) {
            wrong.add(call.getKey() + " threw a NullPointerException saying " + message);
          }
        } catch (Throwable t) {
          wrong.add(call.getKey() + " threw " + t);
        }
      }
      assertEquals(List.of(), wrong, "each null is refused with a NullPointerException naming it");
      events.publish(1);
      assertEquals(1, takeOrFail(reader), "the source still carries values after the refused calls");
    }
  }

  /**
   * {@link PrimeCore#serviceNames()}: "in declaration order: every chain made of a block, every
   * template chain and every filter, flat-map and listener; linked chains and sources are not
   * services", and every combinator, timer and generic service, each "a service of this core":
   * a core declaring one of each kind lists exactly those, in the order they were declared.
   */
  @Test
  default void serviceNamesListEveryKindOfServiceInDeclarationOrder() {
    try (PrimeCore core = newCore()) {
      Source<Integer> a = core.source("a", new EventBlock<Integer>());
      Source<Integer> b = core.source("b", new EventBlock<Integer>());
      a.then(core.chain("double", (Integer x) -> 2 * x).then(core.chain("inc", (Integer x) -> x + 1)));
      core.union(core.chain("left", (Integer x) -> x), core.chain("right", (Integer x) -> x));
      a.filter(x -> x > 0);
      a.flatMap(x -> List.of(x));
      a.listen(x -> {});
      core.zip(a, b);
      core.timer("beat", Duration.ofHours(1));
      core.service("driver", () -> Thread.sleep(patience().toMillis()));
      a.sample(Duration.ofHours(1));
      assertEquals(
          List.of(
              "double",
              "inc",
              "left",
              "right",
              "union(left|right)",
              "filter(a)",
              "flatMap(a)",
              "listen(a)",
              "zip(a|b)",
              "beat",
              "driver",
              "sample(a)"),
          List.copyOf(core.serviceNames()));
    }
  }

  /**
   * A name is unique among a core's chains, sources and services of every kind (architecture,
   * <i>Generic services</i>, "In the diagram": "Its name is unique among the core's chains,
   * sources and services"; the topology model names each node once): a chain, an event source, a
   * timer and a generic service cannot take a name another of them has, whichever came first.
   * The refusal is an {@link IllegalArgumentException} naming the name, and it changes nothing:
   * the topology keeps only the first, and the refused generic service never runs.
   */
  @Test
  default void aNameIsTakenOnceWhateverKindOfNodeTookIt() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      core.chain("a-chain", (Integer x) -> x);
      core.source("a-source", new EventBlock<Integer>());
      core.timer("a-timer", Duration.ofHours(1));
      core.service("a-service", () -> Thread.sleep(patience().toMillis()));
      int nodes = core.topology().nodes().size();
      List<String> wrong = new ArrayList<>();
      for (String taken : List.of("a-chain", "a-source", "a-timer", "a-service")) {
        Map<String, Executable> again = new LinkedHashMap<>();
        again.put("chain", () -> core.chain(taken, (Integer x) -> x));
        again.put("source", () -> core.source(taken, new EventBlock<Integer>()));
        again.put("timer", () -> core.timer(taken, Duration.ofHours(1)));
        again.put(
            "service",
            () ->
                core.service(
                    taken,
                    () -> {
                      throw new AssertionError("a refused service ran");
                    }));
        for (Map.Entry<String, Executable> call : again.entrySet()) {
          try {
            call.getValue().execute();
            wrong.add("a " + call.getKey() + " named '" + taken + "' was accepted");
          } catch (IllegalArgumentException e) {
            if (e.getMessage() == null || !e.getMessage().contains(taken)) {
              wrong.add("a " + call.getKey() + " named '" + taken + "': " + e.getMessage());
            }
          } catch (Throwable t) {
            wrong.add("a " + call.getKey() + " named '" + taken + "' threw " + t);
          }
        }
      }
      assertEquals(List.of(), wrong, "every taken name is refused, naming it");
      assertEquals(nodes, core.topology().nodes().size(), "the refusals added no node");
      core.start();
    }
  }

  /**
   * The start line lists "the services this process hosts (the first 20, and how many more)"
   * (architecture, <i>Values</i>, the logging list): a core hosting 25 named chains linked to a
   * source logs one INFO line naming the first 20 services in declaration order, none after them,
   * and how many more there are.
   */
  @Test
  default void theStartLineNamesTheFirstTwentyServicesAndCountsTheRest() {
    if (!logsStartLine()) {
      return;
    }
    String tag = UUID.randomUUID().toString().substring(0, 8);
    List<String> starts;
    List<String> services;
    String coreName;
    try (CapturedStderr err = new CapturedStderr()) {
      try (PrimeCore core = newCore(CoreConfig.defaults())) {
        coreName = core.name();
        Source<Integer> source = core.source("feed-" + tag, new EventBlock<Integer>());
        for (int i = 1; i <= 25; i++) {
          core.link(source, core.chain(String.format("s%02d-%s", i, tag), (Integer x) -> x));
        }
        services = List.copyOf(core.serviceNames());
        core.start();
      }
      starts =
          err.lines().stream()
              .filter(l -> l.contains("core '" + coreName + "' started on "))
              .toList();
    }
    assertEquals(1, starts.size(), String.valueOf(starts));
    String line = starts.get(0);
    assertEquals(25, services.size(), "the services: " + services);
    for (int i = 0; i < 20; i++) {
      assertTrue(line.contains(services.get(i)), "names service " + (i + 1) + ": " + line);
    }
    for (int i = 20; i < 25; i++) {
      assertFalse(line.contains(services.get(i)), "leaves out service " + (i + 1) + ": " + line);
    }
    assertTrue(line.contains(" and 5 more"), "says how many more: " + line);
  }
}

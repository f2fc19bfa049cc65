package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Chain;
import dev.prime.ChainAlreadyUsedException;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Repeat;
import dev.prime.Source;
import dev.prime.topology.Topology;
import dev.prime.topology.TopologyNode;
import java.util.ArrayList;
import java.util.List;
import java.util.Optional;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicInteger;
import java.util.concurrent.atomic.AtomicReference;
import java.util.function.Function;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.function.Executable;

/**
 * A failed link changes nothing: every link and template checks all its chains before it
 * consumes any, so giving it a used chain throws {@link ChainAlreadyUsedException} naming that
 * chain and leaves every other chain usable.
 */
public interface AtomicLinkConformance extends ConformanceBase {

  /** One refused call: given the used chain and fresh chains made on demand, it links them. */
  @FunctionalInterface
  interface Refused {
    void link(Chain<Integer, Integer> used, Function<String, Chain<Integer, Integer>> fresh);
  }

  @Test
  default void aLinkOrTemplateRefusingAUsedChainConsumesNothing() {
    List<Refused> refusals =
        List.of(
            (used, fresh) -> fresh.apply("first").then(used),
            (used, fresh) -> used.core().link(fresh.apply("first"), used),
            (used, fresh) -> used.core().link(used, fresh.apply("second")),
            (used, fresh) -> used.core().ifThenElse(x -> true, fresh.apply("then"), used),
            (used, fresh) -> used.core().ifThenElse(x -> true, used, fresh.apply("else")),
            (used, fresh) -> used.core().forEach(used),
            (used, fresh) -> used.core().union(fresh.apply("a"), used),
            (used, fresh) -> used.core().union(fresh.apply("a"), fresh.apply("b"), used),
            (used, fresh) ->
                used.core().union(fresh.apply("a"), fresh.apply("b"), fresh.apply("c"), used),
            (used, fresh) ->
                used.core()
                    .union(
                        fresh.apply("a"), fresh.apply("b"), fresh.apply("c"), fresh.apply("d"), used),
            (used, fresh) -> used.core().fork(used, new EventBlock<Integer>()),
            (used, fresh) -> used.core().guard(x -> true, used, x -> x),
            (used, fresh) -> used.core().isolate(used),
            (used, fresh) ->
                used.core().repeater(used, (Integer in, Integer out, List<Void> none) -> Repeat.stop(out)),
            (used, fresh) ->
                used.core()
                    .repeater(
                        used,
                        used.core().source(new EventBlock<String>()),
                        (Integer in, Integer out, List<String> seen) -> Repeat.stop(out)),
            (used, fresh) -> used.core().link(used.core().source(new EventBlock<Integer>()), used),
            (used, fresh) -> used.core().source(new EventBlock<Integer>()).then(used));
    for (int i = 0; i < refusals.size(); i++) {
      Refused refused = refusals.get(i);
      String what = "refusal " + (i + 1);
      try (PrimeCore core = newCore()) {
        Chain<Integer, Integer> used = core.chain("used", x -> x);
        used.toBlock();
        List<Chain<Integer, Integer>> others = new ArrayList<>();
        Executable call =
            () ->
                refused.link(
                    used,
                    role -> {
                      Chain<Integer, Integer> chain = core.chain(role, (Integer x) -> x + 1);
                      others.add(chain);
                      return chain;
                    });
        ChainAlreadyUsedException e = assertThrows(ChainAlreadyUsedException.class, call, what);
        assertEquals("used", e.chainName(), what + ": the used chain is blamed");
        core.start();
        for (Chain<Integer, Integer> other : others) {
          assertEquals(
              2, other.toBlock().process(1), what + ": chain '" + other.name() + "' is still usable");
        }
      }
    }
  }

  /** A source of {@code owner} whose readers cannot be opened: a link to it fails late. */
  static Source<Integer> sourceWithoutReaders(PrimeCore owner) {
    return new Source<>() {
      @Override
      public PrimeCore core() {
        return owner;
      }

      @Override
      public String name() {
        return "unreadable";
      }

      @Override
      public Reader<Integer> reader() {
        throw new IllegalStateException("this source cannot be read");
      }
    };
  }

  @Test
  default void aSourceLinkThatFailsAfterItsCheckConsumesAndRecordsNothing() {
    try (PrimeCore core = newCore();
        PrimeCore other = newCore()) {
      Source<Integer> unreadable = sourceWithoutReaders(other);
      Chain<Integer, Integer> chain = core.chain("survivor", x -> x + 1);
      Topology before = core.topology();
      IllegalStateException e =
          assertThrows(IllegalStateException.class, () -> core.link(unreadable, chain));
      assertEquals("this source cannot be read", e.getMessage());
      assertEquals(before, core.topology(), "the failed link left no node behind");
      core.start();
      assertEquals(2, chain.toBlock().process(1), "the chain is still usable");
    }
  }

  /**
   * A declaration that fails leaves the chain unused; it can be made again: on a started core, a
   * link of a chain to a source whose reader cannot be opened the first time fails, and the same
   * link, of the same chain, works once the cause is gone, as a first link would.
   */
  @Test
  default void aSourceLinkThatFailedAfterStartCanBeMadeAgain() throws Exception {
    try (PrimeCore core = newCore();
        PrimeCore other = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> numbers = other.source("numbers", events);
      AtomicInteger opened = new AtomicInteger();
      Source<Integer> flaky = failingFirstReader(numbers, opened);
      other.start();
      core.start();
      Chain<Integer, Integer> chain = core.chain("retried", x -> x + 1);
      IllegalStateException e =
          assertThrows(IllegalStateException.class, () -> core.link(flaky, chain));
      assertEquals("this source cannot be read yet", e.getMessage());
      Reader<Integer> results = core.link(flaky, chain).reader();
      assertEquals(2, opened.get(), "the link was made again");
      events.publish(1);
      assertEquals(
          Optional.of(2), results.take(patience()), "the link made again runs the chain");
    }
  }

  /**
   * The same for a chain of another core, which the link takes through its {@code toBlock()}: a
   * link that fails leaves that chain unused too, and the same link works once the cause is gone.
   */
  @Test
  default void aSourceLinkOfAnotherCoresChainThatFailedLeavesThatChainUnused() throws Exception {
    try (PrimeCore core = newCore();
        PrimeCore other = newCore();
        PrimeCore owner = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> numbers = other.source("numbers", events);
      AtomicInteger opened = new AtomicInteger();
      Source<Integer> flaky = failingFirstReader(numbers, opened);
      Chain<Integer, Integer> chain = owner.chain("owned", x -> x + 1);
      owner.start();
      other.start();
      core.start();
      IllegalStateException e =
          assertThrows(IllegalStateException.class, () -> core.link(flaky, chain));
      assertEquals("this source cannot be read yet", e.getMessage());
      Reader<Integer> results = core.link(flaky, chain).reader();
      assertEquals(2, opened.get(), "the link was made again");
      events.publish(1);
      assertEquals(
          Optional.of(2), results.take(patience()), "the link made again runs the other core's chain");
    }
  }

  /** {@code source}, whose first reader cannot be opened; counts the readers asked for. */
  static Source<Integer> failingFirstReader(Source<Integer> source, AtomicInteger opened) {
    return new Source<>() {
      @Override
      public PrimeCore core() {
        return source.core();
      }

      @Override
      public String name() {
        return "flaky";
      }

      @Override
      public Reader<Integer> reader() {
        if (opened.incrementAndGet() == 1) {
          throw new IllegalStateException("this source cannot be read yet");
        }
        return source.reader();
      }
    };
  }

  @Test
  default void concurrentLinksSharingAChainConsumeOnlyTheWinnersChains() throws Exception {
    int trials = 200;
    try (PrimeCore core = newCore()) {
      List<Chain<Integer, Integer>> losers = new ArrayList<>();
      int links = 0;
      for (int trial = 0; trial < trials; trial++) {
        Chain<Integer, Integer> shared = core.chain("shared-" + trial, x -> x * 10);
        Chain<Integer, Integer> b = core.chain("b-" + trial, x -> x + 1);
        Chain<Integer, Integer> c = core.chain("c-" + trial, x -> x + 2);
        CountDownLatch go = new CountDownLatch(1);
        AtomicReference<Object> byB = new AtomicReference<>();
        AtomicReference<Object> byC = new AtomicReference<>();
        Thread tb = linker(go, () -> core.link(b, shared), byB);
        Thread tc = linker(go, () -> core.link(c, shared), byC);
        go.countDown();
        tb.join(patience().toMillis());
        tc.join(patience().toMillis());
        assertTrue(!tb.isAlive() && !tc.isAlive(), "trial " + trial + ": a link did not return");
        boolean bWon = byB.get() instanceof Chain<?, ?>;
        boolean cWon = byC.get() instanceof Chain<?, ?>;
        assertTrue(bWon ^ cWon, "trial " + trial + ": exactly one link wins: " + byB + ", " + byC);
        Object lost = bWon ? byC.get() : byB.get();
        assertTrue(
            lost instanceof ChainAlreadyUsedException used && used.chainName().equals(shared.name()),
            "trial " + trial + ": the loser is refused for the shared chain: " + lost);
        losers.add(bWon ? c : b);
        links++;
      }
      long linkNodes =
          core.topology().nodes().stream().filter(n -> n instanceof TopologyNode.Link).count();
      assertEquals(links, linkNodes, "one Link node per link made");
      core.start();
      for (Chain<Integer, Integer> loser : losers) {
        int expected = loser.name().startsWith("b-") ? 2 : 3;
        assertEquals(expected, loser.toBlock().process(1), loser.name() + " is still usable");
      }
    }
  }

  /** A started thread that links once {@code go} opens and keeps the chain or the exception. */
  private static Thread linker(
      CountDownLatch go, java.util.function.Supplier<Object> link, AtomicReference<Object> result) {
    Thread thread =
        new Thread(
            () -> {
              try {
                if (go.await(60, TimeUnit.SECONDS)) {
                  result.set(link.get());
                }
              } catch (RuntimeException | InterruptedException e) {
                result.set(e);
              }
            },
            "kit-linker");
    thread.setDaemon(true);
    thread.start();
    return thread;
  }
}

package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNotEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.ChainAlreadyUsedException;
import dev.prime.ChainFailedException;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Source;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.ExecutorService;
import java.util.concurrent.Executors;
import java.util.concurrent.Future;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;

/** Chains and links: composition, single use, order and the one-service rule. */
public interface ChainConformance extends ConformanceBase {

  @Test
  default void chainBlockComputes() {
    try (PrimeCore core = newCore()) {
      Chain<Integer, Integer> twice = core.chain("twice", x -> x * 2);
      core.start();
      assertEquals("twice", twice.name());
      assertEquals(core, twice.core());
      assertEquals(42, twice.toBlock().process(21));
    }
  }

  @Test
  default void linkedChainsRunInOrder() {
    try (PrimeCore core = newCore()) {
      Chain<String, String> a = core.chain(s -> s + "a");
      Chain<String, String> b = core.chain(s -> s + "b");
      Chain<String, Integer> len = core.chain(String::length);
      Chain<String, Integer> all = core.link(core.link(a, b), len);
      Chain<String, String> viaThen = core.chain((String s) -> s + "x").then(s -> s + "y");
      core.start();
      Block<String, Integer> block = all.toBlock();
      assertEquals(3, block.process("_"));
      assertEquals(2, block.process(""));
      assertEquals("_xy", viaThen.toBlock().process("_"));
    }
  }

  @Test
  default void derivedNamesAreDistinct() {
    try (PrimeCore core = newCore()) {
      Chain<Integer, Integer> one = core.link(core.chain("a", x -> x), core.chain("b", x -> x));
      Chain<Integer, Integer> unnamed1 = core.chain(x -> x);
      Chain<Integer, Integer> unnamed2 = core.chain(x -> x);
      assertNotEquals(unnamed1.name(), unnamed2.name());
      assertNotEquals(one.name(), unnamed1.name());
      assertTrue(one.name().contains("a") && one.name().contains("b"), one.name());
    }
  }

  @Test
  default void toBlockTwiceIsRefused() {
    try (PrimeCore core = newCore()) {
      Chain<Integer, Integer> chain = core.chain("once", x -> x);
      chain.toBlock();
      ChainAlreadyUsedException e =
          assertThrows(ChainAlreadyUsedException.class, chain::toBlock);
      assertTrue(e.getMessage().contains("once"), e.getMessage());
      assertEquals("once", e.chainName());
    }
  }

  @Test
  default void linkingAUsedChainIsRefused() {
    try (PrimeCore core = newCore()) {
      Chain<Integer, Integer> a = core.chain("a", x -> x);
      Chain<Integer, Integer> b = core.chain("b", x -> x);
      core.link(a, b);
      assertThrows(ChainAlreadyUsedException.class, () -> core.link(a, core.chain((Integer x) -> x)));
      assertThrows(ChainAlreadyUsedException.class, () -> core.link(core.chain((Integer x) -> x), b));
      assertThrows(ChainAlreadyUsedException.class, a::toBlock);
    }
  }

  /**
   * A call that is refused changes nothing (architecture, <i>Errors</i>, "Misuse"): {@code
   * then(block)} of a used chain is refused and leaves no chain of the block behind, so the
   * diagram, its services and the next generated name are what they were.
   */
  @Test
  default void aRefusedThenOfABlockLeavesNoChainBehind() {
    try (PrimeCore core = newCore()) {
      Chain<Integer, Integer> used = core.chain("used", (Integer x) -> x);
      used.toBlock();
      java.util.Set<String> services = core.serviceNames();
      List<dev.prime.topology.TopologyNode> nodes = core.topology().nodes();
      assertThrows(ChainAlreadyUsedException.class, () -> used.then((Integer x) -> x + 1));
      assertEquals(services, core.serviceNames(), "no service was added");
      assertEquals(nodes, core.topology().nodes(), "the diagram is as it was");
      assertEquals("chain-1", core.chain((Integer x) -> x).name(), "the next generated name");
    }
  }

  @Test
  default void linkingAChainToItselfIsRefused() {
    try (PrimeCore core = newCore()) {
      Chain<Integer, Integer> self = core.chain("self", x -> x);
      ChainAlreadyUsedException e =
          assertThrows(ChainAlreadyUsedException.class, () -> core.link(self, self));
      assertTrue(e.getMessage().contains("self"), e.getMessage());
    }
  }

  @Test
  default void chainLinkedToSourceCannotBeReused() {
    try (PrimeCore core = newCore()) {
      Source<Integer> source = core.source(new EventBlock<Integer>());
      Chain<Integer, Integer> chain = core.chain(x -> x);
      core.link(source, chain);
      assertThrows(ChainAlreadyUsedException.class, () -> core.link(source, chain));
      assertThrows(ChainAlreadyUsedException.class, chain::toBlock);
    }
  }

  @Test
  default void linkingChainsFirstMakesOneService() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source("numbers", events);
      Chain<Integer, Integer> plus1 = core.chain("plus1", x -> x + 1);
      Chain<Integer, Integer> times10 = core.chain("times10", x -> x * 10);
      Chain<Integer, String> show = core.chain("show", x -> "v" + x);
      Source<String> out = core.link(source, core.link(core.link(plus1, times10), show));
      // the same services on every media: the three chains (a link is not a service)
      assertEquals(
          List.of("plus1", "times10", "show"), List.copyOf(core.serviceNames()), "services");
      Reader<String> reader = out.reader();
      core.start();
      events.publish(1);
      events.publish(2);
      assertEquals(List.of("v20", "v30"), takeOrFail(reader, 2));
    }
  }

  @Test
  default void linkedChainKeepsOrderOfThousandsOfValues() throws InterruptedException {
    int n = 5000;
    try (PrimeCore core = newCore(dev.prime.CoreConfig.builder().sourceRetention(n).build())) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> source = core.source(events);
      Source<Integer> out = core.link(source, core.link(core.chain(x -> x + 1), core.chain(x -> x * 2)));
      Reader<Integer> direct = source.reader();
      Reader<Integer> linked = out.reader();
      core.start();
      for (int i = 0; i < n; i++) {
        events.publish(i);
      }
      List<Integer> seen = takeOrFail(direct, n);
      List<Integer> transformed = takeOrFail(linked, n);
      List<Integer> expected = new ArrayList<>();
      List<Integer> expectedOut = new ArrayList<>();
      for (int i = 0; i < n; i++) {
        expected.add(i);
        expectedOut.add((i + 1) * 2);
      }
      assertEquals(expected, seen);
      assertEquals(expectedOut, transformed);
      assertEquals(0, linked.missed());
    }
  }

  @Test
  default void chainReturningNullPublishesNothing() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> evens = core.link(core.source(events), core.chain(x -> x % 2 == 0 ? x : null));
      Reader<Integer> reader = evens.reader();
      core.start();
      for (int i = 1; i <= 6; i++) {
        events.publish(i);
      }
      assertEquals(List.of(2, 4, 6), takeOrFail(reader, 3));
      assertTrue(reader.poll().isEmpty());
    }
  }

  /**
   * {@link Block}, "Nulls": chains pass {@code null} between blocks if a block returns it. A
   * synchronous call of a chain whose block returns {@code null} returns {@code null}; in a linked
   * chain the next block gets that {@code null}, also where the linked chain runs as a service on
   * a source (which publishes nothing only for a {@code null} its last block returns).
   */
  @Test
  default void aNullABlockReturnsReachesTheCallerAndTheNextBlock() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      Block<Integer, String> nothing =
          core.chain("nothing", (Integer x) -> (String) null).toBlock();
      Block<Integer, String> linked =
          core.chain("maybe", (Integer x) -> x > 0 ? "p" + x : null)
              .then(core.chain("show", (String s) -> s == null ? "none" : s))
              .toBlock();
      EventBlock<Integer> events = new EventBlock<>();
      Reader<String> shown =
          core.source("maybes", events)
              .then(
                  core.chain("maybe-served", (Integer x) -> x > 0 ? "p" + x : null)
                      .then(core.chain("show-served", (String s) -> s == null ? "none" : s)))
              .reader();
      core.start();
      assertEquals(null, nothing.process(1), "a synchronous call returns the null");
      assertEquals("none", linked.process(-1), "the next block got the null");
      assertEquals("p2", linked.process(2));
      events.publish(-1);
      events.publish(3);
      assertEquals(List.of("none", "p3"), takeOrFail(shown, 2), "the served chain's next block got it");
    }
  }

  @Test
  default void sourceThenChainsAcrossSeveralStages() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      EventBlock<String> events = new EventBlock<>();
      Source<Integer> lengths = core.source(events).then(String::length).then(x -> x * x);
      Reader<Integer> reader = lengths.reader();
      core.start();
      events.publish("ab");
      events.publish("abc");
      assertEquals(List.of(4, 9), takeOrFail(reader, 2));
    }
  }

  @Test
  default void oneChainTwiceInATemplateIsRefused() {
    try (PrimeCore core = newCore()) {
      Chain<Integer, Integer> twice = core.chain("twice-used", x -> x);
      assertThrows(ChainAlreadyUsedException.class, () -> core.ifThenElse(x -> true, twice, twice));
      assertThrows(ChainAlreadyUsedException.class, () -> core.union(twice, twice));
      Chain<Integer, Integer> other = core.chain(x -> x);
      assertThrows(
          ChainAlreadyUsedException.class,
          () -> core.union(other, core.chain((Integer x) -> x), core.chain((Integer x) -> x), core.chain((Integer x) -> x), other));
      Chain<Integer, Integer> fresh = core.chain(x -> x + 1);
      core.start();
      assertEquals(2, fresh.toBlock().process(1), "a refused template consumed nothing else");
    }
  }

  /**
   * {@link Chain#toBlock()}: "The returned block may be called from several threads at once",
   * and a block's exception reaches its caller as a {@link ChainFailedException} naming the chain.
   * Four threads calling the block of a linked chain at once each get the result of their own
   * input, and an input the first chain refuses fails that call only, with the block's own
   * exception as the cause.
   */
  @Test
  default void theBlockOfAChainGivesConcurrentCallersEachTheirOwnResult() throws Exception {
    int callers = 4;
    int calls = 50;
    try (PrimeCore core = newCore()) {
      Block<Integer, Integer> block =
          core.chain(
                  "shift",
                  (Integer x) -> {
                    if (x % 7 == 3) {
                      throw new IllegalArgumentException("refused " + x);
                    }
                    return x + 1;
                  })
              .then(core.chain("double", (Integer x) -> x * 2))
              .toBlock();
      core.start();
      ExecutorService pool = Executors.newFixedThreadPool(callers);
      CountDownLatch go = new CountDownLatch(1);
      try {
        List<Future<Integer>> done = new ArrayList<>();
        for (int c = 0; c < callers; c++) {
          int first = c * 1000;
          done.add(
              pool.submit(
                  () -> {
                    assertTrue(go.await(patience().toMillis(), TimeUnit.MILLISECONDS));
                    int failed = 0;
                    for (int input = first; input < first + calls; input++) {
                      int in = input;
                      if (in % 7 == 3) {
                        ChainFailedException e =
                            assertThrows(ChainFailedException.class, () -> block.process(in));
                        assertEquals("shift", e.chainName());
                        assertEquals("refused " + in, e.getCause().getMessage());
                        failed++;
                      } else {
                        assertEquals((in + 1) * 2, block.process(in), "for input " + in);
                      }
                    }
                    return failed;
                  }));
        }
        go.countDown();
        for (Future<Integer> caller : done) {
          assertTrue(caller.get(patience().toMillis() * 2, TimeUnit.MILLISECONDS) > 0);
        }
      } finally {
        pool.shutdownNow();
      }
    }
  }
}

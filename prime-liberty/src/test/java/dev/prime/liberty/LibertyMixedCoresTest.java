package dev.prime.liberty;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.ChainAlreadyUsedException;
import dev.prime.ChainFailedException;
import dev.prime.CoreClosedException;
import dev.prime.EventBlock;
import dev.prime.Reader;
import dev.prime.Source;
import java.time.Duration;
import java.util.List;
import java.util.Optional;
import org.junit.jupiter.api.Test;

/** Liberty-specific behaviour: chains and sources of several Liberty cores used together. */
class LibertyMixedCoresTest {

  @Test
  void linksAForeignChainThroughItsBlock() {
    try (LibertyCore a = new LibertyCore();
        LibertyCore b = new LibertyCore()) {
      Chain<Integer, Integer> foreign = b.chain("foreign", x -> x * 10);
      Chain<Integer, Integer> linked = a.link(a.chain("own", x -> x + 1), foreign);
      a.start();
      b.start();
      assertEquals(30, linked.toBlock().process(2));
      assertThrows(ChainAlreadyUsedException.class, foreign::toBlock, "the foreign chain is consumed");
    }
  }

  @Test
  void foreignChainFailureStillNamesTheInnermostChain() {
    RuntimeException boom = new IllegalStateException("boom");
    try (LibertyCore a = new LibertyCore();
        LibertyCore b = new LibertyCore()) {
      Chain<Integer, Integer> foreign =
          b.chain(
              "foreign-failing",
              x -> {
                throw boom;
              });
      Block<Integer, Integer> block = a.link(a.chain("own", (Integer x) -> x), foreign).toBlock();
      a.start();
      b.start();
      ChainFailedException e = assertThrows(ChainFailedException.class, () -> block.process(1));
      assertEquals("foreign-failing", e.chainName());
      assertSame(boom, e.getCause());
    }
  }

  @Test
  void libertyBlockInsideAnotherCoresChain() {
    try (LibertyCore a = new LibertyCore();
        LibertyCore b = new LibertyCore()) {
      Block<String, Integer> lengthOfB = b.chain("length", String::length).toBlock();
      Chain<String, Integer> chain = a.chain("wrapper", s -> lengthOfB.process(s) * 2);
      a.start();
      b.start();
      Block<String, Integer> block = chain.toBlock();
      assertEquals(6, block.process("abc"));
      ChainFailedException e = assertThrows(ChainFailedException.class, () -> block.process(null));
      assertEquals("length", e.chainName(), "the innermost chain is named, not the wrapper");
    }
  }

  @Test
  void sourceOfOneCoreFeedsAServiceOfAnother() throws InterruptedException {
    try (LibertyCore a = new LibertyCore();
        LibertyCore b = new LibertyCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> sourceOfB = b.source(events);
      Source<Integer> out = a.link(sourceOfB, a.chain(x -> -x));
      assertEquals(1, a.serviceNames().size());
      assertEquals(0, b.serviceNames().size());
      Reader<Integer> reader = out.reader();
      a.start();
      b.start();
      events.publish(4);
      assertEquals(Optional.of(-4), reader.take(Duration.ofSeconds(20)));
    }
  }

  @Test
  void chainOfAClosedCoreIsRefused() {
    try (LibertyCore a = new LibertyCore()) {
      LibertyCore b = new LibertyCore();
      Chain<Integer, Integer> foreign = b.chain(x -> x);
      b.close();
      CoreClosedException e =
          assertThrows(CoreClosedException.class, () -> a.link(a.chain((Integer x) -> x), foreign));
      assertTrue(e.getMessage().contains(b.name()), e.getMessage());
    }
  }

  @Test
  void linkingOwnChainsComposesOneFlatBlock() {
    try (LibertyCore core = new LibertyCore()) {
      Chain<Integer, Integer> linked =
          core.link(core.link(core.chain(x -> x + 1), core.chain(x -> x * 2)), core.chain(x -> x - 1));
      core.start();
      Block<Integer, Integer> block = linked.toBlock();
      assertInstanceOf(Runs.Run3.class, block,
          "one run of three blocks, not a link of links");
      assertEquals(List.of(3, 5), List.of(block.process(1), block.process(2)));
    }
  }
}

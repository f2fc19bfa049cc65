package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.spi.FailureNamingBlock;
import dev.prime.spi.GenericChainCompiler;
import dev.prime.topology.TopologyNode;
import java.util.List;
import org.junit.jupiter.api.Test;

/** Names made in one place, readers counted per source, and a media's unrecorded chain refused. */
class TopologyRecorderTest {

  /** The generic core with a media mistake on demand: a chain made without the recorder. */
  private static final class PlainCore extends PrimeCore {
    PlainCore() {
      super("plain", CoreConfig.defaults());
    }

    @Override
    protected ChainCompiler<?> chainCompiler() {
      return new GenericChainCompiler();
    }

    /** A chain of this core that a media made without recording it. */
    <I, O> Chain<I, O> unrecorded(String name, Block<I, O> block) {
      PrimeCore self = this;
      return new Chain<>() {
        @Override
        public PrimeCore core() {
          return self;
        }

        @Override
        public String name() {
          return name;
        }

        @Override
        public Block<I, O> toBlock() {
          return new FailureNamingBlock<>(name, block);
        }
      };
    }
  }

  @Test
  void aTakenDerivedNameGetsASuffixAndTheNodeKeepsItsParts() {
    try (PlainCore core = new PlainCore()) {
      core.chain("forEach(body)", (Integer x) -> x); // a user's name that a template would make
      Chain<List<Integer>, List<Integer>> each = core.forEach(core.chain("body", (Integer x) -> x));
      assertEquals("forEach(body)#2", each.name());
      assertEquals(
          new TopologyNode.ForEach("forEach(body)#2", "body"),
          core.topology().node("forEach(body)#2").orElseThrow());
    }
  }

  @Test
  void readersOfTheProgramAreNumberedPerSource() {
    try (PlainCore core = new PlainCore()) {
      Source<Integer> a = core.source("a", new EventBlock<>());
      Source<Integer> b = core.source("b", new EventBlock<>());
      a.reader();
      b.reader();
      a.reader();
      core.syncCollector(a); // the collector's own reader is not the program's
      assertEquals(
          List.of(
              new TopologyNode.ReaderNode("a", 1),
              new TopologyNode.ReaderNode("b", 1),
              new TopologyNode.ReaderNode("a", 2)),
          core.topology().nodes().stream()
              .filter(node -> node instanceof TopologyNode.ReaderNode)
              .toList());
    }
  }

  @Test
  void aChainNotMadeByTheCoreIsRefusedWithTheFix() {
    try (PlainCore core = new PlainCore()) {
      Chain<Integer, Integer> stray = core.unrecorded("stray", x -> x);
      IllegalArgumentException e =
          assertThrows(IllegalArgumentException.class, () -> core.guard(x -> true, stray, x -> 0));
      assertEquals(
          "the chain 'stray' says it belongs to core '" + core.name() + "' but was not made by this"
              + " core's chain(name, block): a chain of your own implementation cannot be linked."
              + " Make it with core.chain(name, block) and give it your logic as a Block",
          e.getMessage());
    }
  }

  @Test
  void aUsersOwnChainAndSourceAreRefusedWithTheFix() {
    try (PlainCore core = new PlainCore()) {
      Chain<Integer, Integer> mine =
          new Chain<>() {
            @Override
            public PrimeCore core() {
              return core;
            }

            @Override
            public String name() {
              return "mine";
            }

            @Override
            public Block<Integer, Integer> toBlock() {
              return x -> x;
            }
          };
      IllegalArgumentException chain =
          assertThrows(
              IllegalArgumentException.class, () -> core.link(core.chain("a", (Integer x) -> x), mine));
      assertTrue(chain.getMessage().contains("not made by this core's chain("), chain.getMessage());
      assertTrue(chain.getMessage().contains("Make it with core.chain("), chain.getMessage());
      Source<Integer> own =
          new Source<>() {
            @Override
            public PrimeCore core() {
              return core;
            }

            @Override
            public String name() {
              return "own";
            }

            @Override
            public dev.prime.Reader<Integer> reader() {
              throw new UnsupportedOperationException();
            }
          };
      IllegalArgumentException source =
          assertThrows(IllegalArgumentException.class, () -> own.listen(x -> {}));
      assertTrue(source.getMessage().contains("the source 'own'"), source.getMessage());
      assertTrue(source.getMessage().contains("core.source(name, events)"), source.getMessage());
      assertEquals(List.of("a"), core.topology().nodes().stream().map(TopologyNode::name).toList());
    }
  }
}

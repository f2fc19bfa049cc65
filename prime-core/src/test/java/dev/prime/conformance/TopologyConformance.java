package dev.prime.conformance;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;
import static org.junit.jupiter.api.Assertions.fail;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.Isolated;
import dev.prime.PrimeCore;
import dev.prime.Reader;
import dev.prime.Repeat;
import dev.prime.Source;
import dev.prime.Token;
import dev.prime.Tuple2;
import dev.prime.topology.Topology;
import dev.prime.topology.TopologyNode;
import dev.prime.topology.TopologyNode.AsyncCollector;
import dev.prime.topology.TopologyNode.BlockChain;
import dev.prime.topology.TopologyNode.EventSource;
import dev.prime.topology.TopologyNode.Filter;
import dev.prime.topology.TopologyNode.FlatMap;
import dev.prime.topology.TopologyNode.ForEach;
import dev.prime.topology.TopologyNode.ForeignChain;
import dev.prime.topology.TopologyNode.ForeignSource;
import dev.prime.topology.TopologyNode.Fork;
import dev.prime.topology.TopologyNode.Guard;
import dev.prime.topology.TopologyNode.IfElse;
import dev.prime.topology.TopologyNode.IsolatedUser;
import dev.prime.topology.TopologyNode.Link;
import dev.prime.topology.TopologyNode.Listener;
import dev.prime.topology.TopologyNode.ReaderNode;
import dev.prime.topology.TopologyNode.Repeater;
import dev.prime.topology.TopologyNode.SourceLink;
import dev.prime.topology.TopologyNode.SyncCollector;
import dev.prime.topology.TopologyNode.Union;
import java.util.List;
import java.util.Set;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.ExecutionException;
import java.util.concurrent.ExecutorService;
import java.util.concurrent.Executors;
import java.util.concurrent.Future;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.TimeoutException;
import java.util.concurrent.atomic.AtomicInteger;
import org.junit.jupiter.api.Test;

/**
 * The topology a core records: every declaration as a node, named in one place, so the same
 * declarations give the same nodes, names and services on every media. Readers the core opens for
 * its own services (links, collectors, filters) are not the program's and are not listed.
 */
public interface TopologyConformance extends ConformanceBase {

  @Test
  default void everyDeclarationIsANodeWithTheSameNameOnEveryMedia() {
    try (PrimeCore core = newCore()) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> numbers = core.source("numbers", events);
      Source<Integer> doubled = numbers.then(core.chain("double", (Integer x) -> x * 2));
      doubled.reader();
      doubled.filter(x -> x > 2).listen(x -> {});
      numbers.flatMap(x -> List.of(x, x));
      Chain<Integer, String> choose =
          core.ifThenElse(
              x -> x > 0, core.chain("pos", (Integer x) -> "+"), core.chain("neg", x -> "-"));
      Chain<List<Integer>, List<String>> each = core.forEach(choose);
      Chain<List<Integer>, Tuple2<List<String>, Integer>> both =
          core.union(each, core.chain("size", List::size));
      Chain<Integer, Integer> forked =
          core.fork(
              core.guard(x -> x > 0, core.chain("inc", (Integer x) -> x + 1), x -> 0),
              new EventBlock<>());
      Isolated<Integer, Integer> shared = core.isolate(core.chain("shared", (Integer x) -> x));
      shared.newUser();
      shared.newUser();
      Chain<Token, Integer> collect = core.syncCollector(doubled);
      core.asyncCollector(numbers);
      core.repeater(
          core.chain("step", (Integer x) -> x + 1),
          numbers,
          (Integer in, Integer out, List<Integer> seen) -> Repeat.<Integer, Integer>stop(out));
      Chain<Token, Integer> called = collect.then(forked);

      List<TopologyNode> expected =
          List.of(
              new EventSource("numbers"),
              new BlockChain("double"),
              new SourceLink("numbers>double", "numbers", "double"),
              new ReaderNode("numbers>double", 1),
              new Filter("filter(numbers>double)", "numbers>double"),
              new Listener("listen(filter(numbers>double))", "filter(numbers>double)"),
              new FlatMap("flatMap(numbers)", "numbers"),
              new BlockChain("pos"),
              new BlockChain("neg"),
              new IfElse("if(pos|neg)", "pos", "neg"),
              new ForEach("forEach(if(pos|neg))", "if(pos|neg)"),
              new BlockChain("size"),
              new Union("union(forEach(if(pos|neg))|size)", List.of("forEach(if(pos|neg))", "size")),
              new BlockChain("inc"),
              new Guard("guard(inc)", "inc"),
              new Fork("fork(guard(inc))", "guard(inc)"),
              new BlockChain("shared"),
              new IsolatedUser("shared@1", "shared"),
              new IsolatedUser("shared@2", "shared"),
              new SyncCollector("collect(numbers>double)", "numbers>double"),
              new AsyncCollector("collectAll(numbers)", "numbers"),
              new BlockChain("step"),
              new AsyncCollector("collectAll(numbers)#2", "numbers"),
              new Repeater("repeat(step)", "step", "collectAll(numbers)#2"),
              new Link(called.name(), "collect(numbers>double)", "fork(guard(inc))"));
      assertEquals(expected, core.topology().nodes());
      assertEquals("collect(numbers>double)>fork(guard(inc))", called.name());
      assertEquals(both.name(), "union(forEach(if(pos|neg))|size)");
      assertEquals(
          List.of(
              "double",
              "filter(numbers>double)",
              "listen(filter(numbers>double))",
              "flatMap(numbers)",
              "pos",
              "neg",
              "if(pos|neg)",
              "forEach(if(pos|neg))",
              "size",
              "union(forEach(if(pos|neg))|size)",
              "inc",
              "guard(inc)",
              "fork(guard(inc))",
              "shared",
              "shared@1",
              "shared@2",
              "collect(numbers>double)",
              "collectAll(numbers)",
              "step",
              "collectAll(numbers)#2",
              "repeat(step)"),
          List.copyOf(core.serviceNames()));
    }
  }

  @Test
  default void chainsAndSourcesOfAnotherCoreAreForeignNodes() throws InterruptedException {
    // declared first, closed last: the local service never sees its foreign source closed
    try (PrimeCore other = newCore(CoreConfig.builder().name("topology-other").build());
        PrimeCore core = newCore()) {
      EventBlock<Integer> readings = new EventBlock<>();
      Source<Integer> theirs = other.source("readings", readings);
      Source<Integer> mine = core.link(theirs, core.chain("local", (Integer x) -> -x));
      Chain<Integer, Integer> mixed =
          core.link(
              core.chain("first", (Integer x) -> x + 1), other.chain("remote", (Integer x) -> x * 10));
      assertEquals(
          List.of(
              new BlockChain("local"),
              new ForeignSource("from(topology-other:readings)", "topology-other", "readings"),
              new SourceLink(mine.name(), "from(topology-other:readings)", "local"),
              new BlockChain("first"),
              new ForeignChain("hosted(remote)", "topology-other", "remote"),
              new Link(mixed.name(), "first", "hosted(remote)")),
          core.topology().nodes().subList(0, 6));
      assertEquals("readings>local", mine.name());
      assertEquals("first>remote", mixed.name());
      assertEquals(List.of("local", "first", "hosted(remote)"), List.copyOf(core.serviceNames()));
      assertEquals(List.of(new EventSource("readings"), new BlockChain("remote")), other.topology().nodes());

      Reader<Integer> reader = mine.reader();
      other.start();
      core.start();
      assertEquals(40, mixed.toBlock().process(3), "the mixed chain runs both parts");
      readings.publish(5);
      assertEquals(-5, takeOrFail(reader), "the foreign source feeds the local service");
    }
  }

  /**
   * A derived name longer than 120 characters becomes {@code kind-N} ({@code link-1}, {@code
   * filter-1}), the same on every media, and what is so named runs as any other (architecture,
   * <i>The diagram as data: the topology model</i>, "Names come from one place").
   */
  @Test
  default void aDerivedNameLongerThan120CharactersBecomesKindN() throws InterruptedException {
    try (PrimeCore core = newCore()) {
      Chain<Integer, Integer> linked =
          core.link(
              core.chain("a".repeat(70), (Integer x) -> x + 1),
              core.chain("b".repeat(60), (Integer x) -> x * 2));
      assertEquals("link-1", linked.name(), "a>b would be 131 characters");
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> passed = core.source("s".repeat(113), events).filter(x -> x > 0);
      assertEquals("filter-1", passed.name(), "filter(s) would be 121 characters");
      Source<Integer> out = passed.then(linked);
      assertEquals("filter-1>link-1", out.name());
      assertEquals(
          List.of(
              new Link("link-1", "a".repeat(70), "b".repeat(60)),
              new Filter("filter-1", "s".repeat(113))),
          core.topology().nodes().stream()
              .filter(node -> node instanceof Link || node instanceof Filter)
              .filter(node -> !node.name().contains(">"))
              .toList());
      Reader<Integer> reader = out.reader();
      core.start();
      events.publish(-1);
      events.publish(3);
      assertEquals(8, takeOrFail(reader), "the filter and the linked chain ran under their names");
    }
  }

  /**
   * {@link Source#conflatedReader()}: "a new reader, recorded in the topology like {@link
   * Source#reader()}": a plain reader and a conflated one of one source are its readers 1 and 2,
   * and a reader of the conflated reader's source made afterwards is number 3.
   */
  @Test
  default void aConflatedReaderIsRecordedInTheTopologyLikeAReader() {
    try (PrimeCore core = newCore()) {
      Source<Integer> pose = core.source("pose", new EventBlock<Integer>());
      pose.reader();
      pose.conflatedReader();
      pose.reader();
      assertEquals(
          List.of(
              new EventSource("pose"),
              new ReaderNode("pose", 1),
              new ReaderNode("pose", 2),
              new ReaderNode("pose", 3)),
          core.topology().nodes());
    }
  }

  /**
   * {@link PrimeCore#source(EventBlock)}: "Creates a source named {@code source-N}", a name
   * unique within its core ({@link Source#name()}): unnamed sources are {@code source-1}, {@code
   * source-2}, ..., skipping a name the program gave a source of its own, and a chain linked to one
   * makes a source named {@code source>chain} ({@link PrimeCore#link}).
   */
  @Test
  default void anUnnamedSourceIsNamedSourceNAndItsLinkSourceGreaterChain() {
    try (PrimeCore core = newCore()) {
      Source<Integer> first = core.source(new EventBlock<Integer>());
      Source<Integer> mine = core.source("source-2", new EventBlock<Integer>());
      Source<Integer> third = core.source(new EventBlock<Integer>());
      Source<Integer> linked = core.link(first, core.chain("half", (Integer x) -> x / 2));
      assertEquals(
          List.of("source-1", "source-2", "source-3", "source-1>half"),
          List.of(first.name(), mine.name(), third.name(), linked.name()));
    }
  }

  /**
   * {@link PrimeCore#topology()} and {@link PrimeCore#serviceNames()}: they "never wait for a
   * declaration under way on another thread", and show every finished declaration and nothing of
   * the one under way. The declaration is held in its checks by a chain of the program's own
   * implementation, whose {@code core()} waits on a latch there; it is then refused and leaves
   * nothing, so the topology is what it was before.
   */
  @Test
  default void topologyNeverWaitsForADeclarationUnderWay() throws Exception {
    long patience = patience().toMillis();
    try (PrimeCore core = newCore()) {
      Chain<Integer, Integer> first = core.chain("first", (Integer x) -> x + 1);
      core.source("numbers", new EventBlock<Integer>());
      Topology before = core.topology();
      Set<String> servicesBefore = core.serviceNames();
      CountDownLatch inside = new CountDownLatch(1);
      CountDownLatch release = new CountDownLatch(1);
      AtomicInteger calls = new AtomicInteger();
      Chain<Integer, Integer> held =
          new Chain<>() {
            @Override
            public PrimeCore core() {
              // the first call picks the cores whose declaration locks the link takes; the second
              // is the declaration's own check, made holding them
              if (calls.incrementAndGet() == 2) {
                inside.countDown();
                try {
                  release.await(patience, TimeUnit.MILLISECONDS);
                } catch (InterruptedException e) {
                  Thread.currentThread().interrupt();
                }
              }
              return core;
            }

            @Override
            public String name() {
              return "held";
            }

            @Override
            public Block<Integer, Integer> toBlock() {
              throw new UnsupportedOperationException("a chain of the program's own, never run");
            }
          };
      ExecutorService threads = Executors.newFixedThreadPool(3);
      try {
        Future<Chain<Integer, Integer>> declaring = threads.submit(() -> core.link(first, held));
        assertTrue(inside.await(patience, TimeUnit.MILLISECONDS), "the declaration is under way");
        Future<Topology> topology = threads.submit(core::topology);
        Future<Set<String>> services = threads.submit(core::serviceNames);
        try {
          assertEquals(before, topology.get(patience, TimeUnit.MILLISECONDS));
          assertEquals(servicesBefore, services.get(patience, TimeUnit.MILLISECONDS));
        } catch (TimeoutException e) {
          fail("topology() or serviceNames() waited " + patience + " ms for a declaration under way");
        }
        assertFalse(declaring.isDone(), "the declaration is still under way");
        release.countDown();
        ExecutionException refused =
            assertThrows(
                ExecutionException.class, () -> declaring.get(patience, TimeUnit.MILLISECONDS));
        assertInstanceOf(IllegalArgumentException.class, refused.getCause());
        assertEquals(before, core.topology(), "the refused declaration left nothing");
        assertFalse(
            core.topology().node("first>held").isPresent(), "no node of the refused link");
      } finally {
        release.countDown();
        threads.shutdownNow();
        assertTrue(threads.awaitTermination(patience, TimeUnit.MILLISECONDS), "the threads ended");
      }
    }
  }
}

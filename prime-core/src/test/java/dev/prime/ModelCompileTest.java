package dev.prime;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import dev.prime.spi.FailureNamingBlock;
import dev.prime.topology.TopologyNode;
import java.lang.ref.WeakReference;
import java.time.Duration;
import java.util.ArrayList;
import java.util.Collections;
import java.util.List;
import java.util.Optional;
import java.util.function.Consumer;
import java.util.function.Predicate;
import org.junit.jupiter.api.Test;

/**
 * A media is a compiler of the topology model: it is given each node with the logic the user
 * wrote and its parts' compiled forms, and nothing else; what it declines becomes the core's
 * generic block. Sources are a media's own by their compiled form, never by their class.
 */
class ModelCompileTest {

  /** One call a media's compiler received. */
  record Call(String method, String node, Object logic, List<String> parts) {}

  /** A form that remembers which node it was compiled from. */
  record Form(String node, Block<?, ?> block) {}

  /** Compiles to blocks like the generic compiler, recording every call; fuses if/else only. */
  static final class RecordingCompiler implements ChainCompiler<Form> {
    final List<Call> calls = Collections.synchronizedList(new ArrayList<>());
    volatile Consumer<String> onForeign = node -> {};

    @Override
    public Class<Form> form() {
      return Form.class;
    }

    @Override
    @SuppressWarnings({"unchecked", "rawtypes"})
    public Form block(String chain, Block<?, ?> block) {
      calls.add(new Call("block", chain, block, List.of()));
      return new Form(chain, new FailureNamingBlock(chain, block));
    }

    @Override
    public Form foreign(String node, Block<?, ?> block) {
      onForeign.accept(node);
      calls.add(new Call("foreign", node, block, List.of()));
      return new Form(node, block);
    }

    @Override
    @SuppressWarnings({"unchecked", "rawtypes"})
    public Form template(TopologyNode node, NodeLogic logic, List<Form> parts) {
      calls.add(new Call("template", node.name(), logic, parts.stream().map(Form::node).toList()));
      if (!(node instanceof TopologyNode.IfElse)) {
        return null;
      }
      Predicate condition = ((NodeLogic.Condition) logic).condition();
      Block then = parts.get(0).block();
      Block otherwise = parts.get(1).block();
      return new Form(node.name(), new IfThenElseBlock(condition, then, otherwise));
    }

    @Override
    public Block<?, ?> toBlock(String chain, Form form) {
      return form.block();
    }

    List<Call> of(String node) {
      synchronized (calls) {
        return calls.stream().filter(c -> c.node().equals(node)).toList();
      }
    }
  }

  /** A source of the test media: in memory, with a tag for its compiled form. */
  record Tag(String name) {}

  /** Makes the test media's sources and records the services it compiles. */
  static final class RecordingSources implements SourceCompiler<Tag> {
    final List<Call> services = Collections.synchronizedList(new ArrayList<>());
    PrimeCore core;

    @Override
    public Class<Tag> form() {
      return Tag.class;
    }

    @Override
    public <T> Source<T> eventSource(String name, EventBlock<T> events) {
      return new TaggedSource<>(core, name);
    }

    @Override
    public Source<?> service(TopologyNode node, NodeLogic logic, Tag input, Object chain) {
      services.add(
          new Call("service", node.name(), logic, chain == null ? List.of(input.name()) : List.of(
              input.name(), ((Form) chain).node())));
      return node instanceof TopologyNode.Listener ? null : new TaggedSource<>(core, node.name());
    }
  }

  /** A source whose compiled form is its tag. */
  record TaggedSource<T>(PrimeCore core, String name) implements MediaSource<T> {
    @Override
    public Reader<T> reader() {
      throw new UnsupportedOperationException("the test media's sources are not read");
    }

    @Override
    public Reader<T> serviceReader() {
      throw new UnsupportedOperationException("read in memory: " + name);
    }

    @Override
    public Object compiledForm() {
      return new Tag(name);
    }
  }

  static final class TestMedia extends PrimeCore {
    final RecordingCompiler compiler = new RecordingCompiler();
    final RecordingSources sources;

    TestMedia(boolean ownSources) {
      super("test", CoreConfig.defaults());
      sources = ownSources ? new RecordingSources() : null;
      if (sources != null) {
        sources.core = this;
      }
    }

    @Override
    protected ChainCompiler<?> chainCompiler() {
      return compiler;
    }

    @Override
    protected SourceCompiler<?> sourceCompiler() {
      return sources;
    }

    NodeLogic logic(String node) {
      return topologyRecorder().logic(node);
    }
  }

  @Test
  void eachNodeIsCompiledFromItsLogicAndItsPartsForms() {
    try (TestMedia core = new TestMedia(false)) {
      Block<Integer, Integer> plus = x -> x + 1;
      Block<Integer, Integer> minus = x -> x - 1;
      Predicate<Integer> positive = x -> x > 0;
      Chain<Integer, Integer> chosen =
          core.ifThenElse(positive, core.chain("plus", plus), core.chain("minus", minus));

      assertEquals(List.of(new Call("block", "plus", plus, List.of())), core.compiler.of("plus"));
      assertEquals(
          List.of(
              new Call(
                  "template", "if(plus|minus)", new NodeLogic.Condition(positive),
                  List.of("plus", "minus"))),
          core.compiler.of("if(plus|minus)"),
          "the template got the user's predicate as the node's logic, and its parts' forms");
      IllegalStateException released =
          assertThrows(IllegalStateException.class, () -> core.logic("plus"));
      assertTrue(released.getMessage().contains("released"), released.getMessage());
      core.start();
      Block<Integer, Integer> block = chosen.toBlock();
      assertEquals(3, block.process(2));
      assertEquals(-3, block.process(-2));
    }
  }

  @Test
  void aTemplateTheMediaDeclinesBecomesTheGenericBlockOverItsParts() {
    try (TestMedia core = new TestMedia(false)) {
      EventBlock<Integer> events = new EventBlock<>();
      Chain<Integer, Integer> forked = core.fork(core.chain("twice", (Integer x) -> 2 * x), events);
      List<Call> calls = core.compiler.of("fork(twice)");
      assertEquals(2, calls.size(), calls.toString());
      assertEquals(new Call("template", "fork(twice)", new NodeLogic.Events(events), List.of("twice")),
          calls.get(0));
      assertEquals("block", calls.get(1).method());
      assertEquals("dev.prime.ForkBlock", calls.get(1).logic().getClass().getName());
      core.start();
      assertEquals(6, forked.toBlock().process(3));
    }
  }

  @Test
  void anotherCoresChainIsAForeignNodeCompiledFromThatChainsBlock() {
    try (TestMedia core = new TestMedia(false);
        TestMedia other = new TestMedia(false)) {
      Chain<Integer, Integer> theirs = other.chain("theirs", (Integer x) -> x * 10);
      core.compiler.onForeign =
          node -> {
            // while the link is declared, the foreign node's logic is that chain
            NodeLogic logic = core.logic(node);
            assertInstanceOf(NodeLogic.OtherChain.class, logic);
            assertSame(theirs, ((NodeLogic.OtherChain) logic).chain());
          };
      Chain<Integer, Integer> linked = core.chain("mine", (Integer x) -> x + 1).then(theirs);
      assertThrows(IllegalStateException.class, () -> core.logic("hosted(theirs)"), "released");
      assertEquals("foreign", core.compiler.of("hosted(theirs)").get(0).method());
      assertEquals(List.of("mine", "hosted(theirs)"), core.compiler.of("mine>theirs").get(0).parts());
      assertThrows(ChainAlreadyUsedException.class, theirs::toBlock, "consumed by the link");
      core.start();
      other.start();
      assertEquals(30, linked.toBlock().process(2));
    }
  }

  @Test
  void servicesOfTheMediasOwnSourcesAreCompiledByItWithTheirLogic() {
    try (TestMedia core = new TestMedia(true)) {
      Source<Integer> ticks = core.source("ticks", new EventBlock<>());
      assertInstanceOf(TaggedSource.class, ticks, "the media made the event source");
      Predicate<Integer> even = x -> x % 2 == 0;
      Consumer<Integer> sink = x -> {};
      Source<Integer> evens = ticks.filter(even);
      ticks.listen(sink);
      Source<Integer> doubled = ticks.then(core.chain("double", (Integer x) -> 2 * x));
      assertEquals(
          List.of(
              new Call("service", "filter(ticks)", new NodeLogic.Condition(even), List.of("ticks")),
              new Call("service", "listen(ticks)", new NodeLogic.Listen(sink), List.of("ticks")),
              new Call("service", "ticks>double", NodeLogic.None.NONE, List.of("ticks", "double"))),
          core.sources.services);
      assertEquals("filter(ticks)", evens.name());
      assertEquals("ticks>double", doubled.name());
    }
  }

  @Test
  void aSourceOfAnotherCoreOfTheSameMediaAndFormIsNotThisMediasOwn() {
    try (TestMedia core = new TestMedia(true);
        TestMedia twin = new TestMedia(true)) {
      Source<Integer> theirs = twin.source("theirs", new EventBlock<>());
      assertInstanceOf(TaggedSource.class, theirs);
      UnsupportedOperationException inMemory =
          assertThrows(
              UnsupportedOperationException.class,
              () -> core.link(theirs, core.chain((Integer x) -> x)));
      assertEquals("read in memory: theirs", inMemory.getMessage());
      assertTrue(core.sources.services.isEmpty() && twin.sources.services.isEmpty());
    }
  }

  @Test
  void aSourceOfAnotherCoreIsReadInMemoryNotCompiled() throws Exception {
    try (TestMedia core = new TestMedia(true);
        TestMedia plain = new TestMedia(false)) {
      EventBlock<Integer> events = new EventBlock<>();
      Source<Integer> elsewhere = plain.source("elsewhere", events); // an in-memory source
      assertNull(((MediaSource<?>) elsewhere).compiledForm());
      Source<Integer> passed = core.link(elsewhere, core.chain("inc", (Integer x) -> x + 1));
      assertTrue(core.sources.services.isEmpty(), core.sources.services.toString());
      Reader<Integer> reader = passed.reader();
      core.start();
      plain.start();
      events.publish(41);
      assertEquals(Optional.of(42), reader.take(Duration.ofSeconds(10)));
    }
  }

  @Test
  void theRecorderReleasesADroppedChainsBlock() {
    try (TestMedia core = new TestMedia(false)) {
      WeakReference<Block<Integer, Integer>> block = dropChain(core, 3);
      for (int round = 0; round < 50 && block.get() != null; round++) {
        System.gc();
      }
      assertNull(block.get(), "the block of a chain nobody holds is still reachable");
      assertEquals(1, core.topology().nodes().size(), "its node is kept, without its logic");
    }
  }

  /** Makes a chain of a fresh block, drops both and returns a weak reference to the block. */
  private static WeakReference<Block<Integer, Integer>> dropChain(TestMedia core, int k) {
    Block<Integer, Integer> block = x -> x + k; // captures k: a new object, not a cached lambda
    core.chain("dropped", block);
    core.compiler.calls.clear(); // the test's compiler records what it was given
    return new WeakReference<>(block);
  }
}

package dev.prime;

import dev.prime.topology.TopologyNode;
import java.time.Instant;
import java.util.ArrayList;
import java.util.List;
import java.util.Objects;
import java.util.function.Supplier;

/**
 * Compiles the chain nodes of a core's topology model with its media's {@link ChainCompiler}: the
 * one place that says what each kind of chain node is made of and, for the templates a media does
 * not compile in its own way, which generic block ({@link IfThenElseBlock}, {@link UnionBlock},
 * ...) runs it.
 *
 * <p>A node is compiled as soon as it is recorded, from the node, its {@link NodeLogic} and the
 * compiled forms of its parts (which it consumes): bottom-up, without recursion, each node once.
 * Event sources and the services of the media's own sources go to its {@link SourceCompiler}, if
 * it has one; otherwise (and for services of any other source) to the core's in-memory one
 * ({@link InProcessServices}). The shared block of {@link PrimeCore#isolate} is built here too.
 *
 * <p>Design note. Stateless apart from its final references to the core, the media's compilers
 * and the core's recording points (which keep their own state): every call reads what it needs from the recorder and runs inside the declaration
 * that recorded the node ({@link TopologyRecorder#declare}), which makes it atomic. It takes
 * this core's parts without consuming them, takes other cores' chains last (their {@link
 * Chain#toBlock()} consumes them), compiles, and only then claims this core's parts.
 *
 * @param <F> the media's compiled form
 */
final class ModelCompiler<F> {
  private final PrimeCore core;
  private final ChainCompiler<F> media;
  private final SourceCompiler<?> sources; // null: in-memory sources
  private final InProcessServices memory; // the in-memory source compiler
  private final RecordingPoints recording; // null: recording is off
  private final MeteringPoints metering; // null: metrics are off

  ModelCompiler(
      PrimeCore core, ChainCompiler<F> media, SourceCompiler<?> sources, InProcessServices memory) {
    this.core = core;
    this.media = Objects.requireNonNull(media, "the media's chain compiler");
    this.sources = sources;
    this.memory = memory;
    RecordingOptions options = core.config().recording();
    this.recording = options == null ? null : new RecordingPoints(core, options, memory);
    this.metering =
        core.config().metrics()
            ? new MeteringPoints(core, core.mediaName(), gauges(), memory)
            : null;
    memory.meterWith(metering);
  }

  /** The media's gauges of its services, if its chain or source compiler has them. */
  private ServiceGauges gauges() {
    if (media instanceof ServiceGauges gauges) {
      return gauges;
    }
    return sources instanceof ServiceGauges gauges ? gauges : null;
  }

  /** The core's metrics; throws if metrics are off. */
  Metrics metrics() {
    if (metering == null) {
      throw new IllegalStateException(
          "metrics are off in core '" + core.name() + "': turn them on with"
              + " CoreConfig.builder().metrics(true) given to the core's constructor");
    }
    return metering.metrics();
  }

  /** The core closed: the metrics, if on, write what their logs still owe. */
  void closed() {
    if (metering != null) {
      metering.metrics().closed();
    }
  }

  /** A generic service just recorded as {@code name}, with its tap if metrics are on. */
  GenericService genericService(String name, GenericService service) {
    return metering == null
        ? service
        : metering.genericService(
            core.topologyRecorder().node(name),
            service,
            () -> core.isClosed() || !core.isHostedHere(name));
  }

  /**
   * The input step of combinator {@code name}, whose output source is compiled, with its tap if
   * metrics are on.
   */
  CombinedInputs.InputStep combinator(String name, CombinedInputs.InputStep step) {
    return metering == null ? step : metering.combinator(name, step);
  }

  /** The core's recording; throws if recording is off. */
  Recording recording() {
    if (recording == null) {
      throw new IllegalStateException(
          "recording is off in core '" + core.name() + "': turn it on with"
              + " CoreConfig.builder().recording(RecordingOptions.ring(10_000)) given to the"
              + " core's constructor");
    }
    return recording.recording();
  }

  /** Compiles a just recorded event source: the media's own, or an in-memory one. */
  <T> Source<T> eventSource(String name, EventBlock<T> events) {
    SourceCompiler<?> compiler = sources == null ? memory : sources;
    if (recording == null && metering == null) {
      return compiler.eventSource(name, events);
    }
    TopologyNode node = core.topologyRecorder().node(name);
    MeteringPoints.SourcePoint metered =
        metering == null ? null : metering.beforeSource(node, events);
    // only event sources are recorded: not the output of a timer or a combinator (Recording)
    RecordingPoints.SourcePoint point =
        recording == null || !(node instanceof TopologyNode.EventSource)
            ? null
            : recording.beforeSource(name, events);
    try {
      Source<T> source = compiler.eventSource(name, events);
      if (point != null) {
        point.afterMedia();
      }
      if (metered != null) {
        metered.afterMedia(source);
      }
      return source;
    } catch (RuntimeException | Error failed) {
      if (point != null) {
        point.cancel();
      }
      if (metered != null) {
        metered.cancel();
      }
      throw failed;
    }
  }

  /**
   * Records and counts values the media published to its event source {@code name} together, not
   * through the source's event block (see {@link PrimeCore#publishedTogether}).
   */
  void publishedTogether(
      String name, List<?> values, Instant wallTime, long monotonicNanos, boolean accepted) {
    if (metering != null) {
      metering.countAll(name, values.size(), System.nanoTime() - monotonicNanos, accepted);
    }
    if (recording != null && accepted) {
      recording.recordAll(name, values, wallTime, monotonicNanos);
    }
  }

  /**
   * Compiles a just recorded service of a source (a source link, filter, flat-map or listener),
   * consuming {@code chain} (a source link's; {@code null} for the other services): by the
   * media's {@link SourceCompiler} if the source is one of its own (in its form), else in memory.
   * If that fails, the chain stays unused (the media left nothing behind), unless the media
   * throws a {@link ChainAlreadyUsedException} naming it: it could not undo what it began.
   *
   * @return the source of its outputs; {@code null} for a listener
   */
  @SuppressWarnings("unchecked")
  <T> Source<T> service(String name, Source<?> input, Chain<?, ?> chain) {
    TopologyRecorder model = core.topologyRecorder();
    TopologyNode node = model.node(name);
    NodeLogic logic = model.logic(name);
    Part<F> part = null;
    if (node instanceof TopologyNode.SourceLink link) {
      part = part(chain, link.chain(), model);
    }
    boolean mediaOwn = sources != null && core.sourcePart(input, sources.form()) != null;
    if (mediaOwn && metering != null && part == null) { // a filter, flat-map or listener
      logic = metering.service(node, logic).logic(); // (in memory, the service meters itself)
    }
    Source<?> output;
    try {
      output =
          mediaOwn
              ? service(sources, node, logic, input, part == null ? null : part.form())
              : memory.service(node, logic, input, part == null ? null : blockOf(part));
    } catch (RuntimeException | Error failed) {
      // a block made of the chain for an in-memory service is taken back; the media may have
      // said that it could not undo what it began with the chain: it then stays consumed
      if (part != null) {
        discardParts(java.util.Collections.singletonList(part), failed);
      }
      throw failed;
    }
    if (part != null) {
      part.claim();
    }
    return (Source<T>) output;
  }

  /** {@link PrimeCore#sourcePart}: the media's form of one of {@code core}'s sources, or null. */
  static <S> S sourceForm(PrimeCore core, Source<?> source, Class<S> form) {
    if (source.core() == core && source instanceof MediaSource<?> own) {
      Object compiled = own.compiledForm();
      if (form.isInstance(compiled)) {
        return form.cast(compiled);
      }
    }
    return null;
  }

  /** A part's block, made when the in-memory service asks for it (its input open). */
  private static Supplier<Block<?, ?>> blockOf(Part<?> part) {
    return part::block;
  }

  /**
   * Compiles the shared block of {@link PrimeCore#isolate}, consuming {@code chain}: the chain's
   * block behind a first-come-first-served queue that never runs it for two callers at once
   * ({@link IsolateBlock}), and ends a waiting
   * caller's wait when the core closes, or when the caller of the call it runs for gave up
   * ({@link PrimeCore#callerGaveUp}). Its users are chain nodes of their own ({@link
   * NodeLogic.Shared}).
   *
   * @param node the shared chain's node, just taken ({@link TopologyRecorder#isolate})
   */
  <I, O> Isolated<I, O> isolate(String node, Chain<I, O> chain) {
    Part<F> part = part(chain, node, core.topologyRecorder());
    @SuppressWarnings("unchecked")
    Block<I, O> shared = new IsolateBlock<>((Block<I, O>) part.block(), core::ensureOpen, core::callerGaveUp);
    part.claim();
    return new IsolatedChain<>(core, node, chain.name(), shared);
  }

  private <S> Source<?> service(
      SourceCompiler<S> media, TopologyNode node, NodeLogic logic, Source<?> input, Object chain) {
    return media.service(node, logic, core.sourcePart(input, media.form()), chain);
  }

  /**
   * Compiles the recorded chain node {@code name}, consuming the chains it is made of.
   *
   * @param name a chain node's name, just recorded
   * @param parts the chains given for its parts, in the order of the node's chain parts (checked
   *     by {@link PrimeCore#requireChains})
   * @return the chain
   */
  <I, O> Chain<I, O> chain(String name, Chain<?, ?>... parts) {
    TopologyRecorder model = core.topologyRecorder();
    TopologyNode node = model.node(name);
    NodeLogic logic = model.logic(name);
    List<String> partNodes = chainParts(node);
    if (partNodes.size() != parts.length) {
      throw new IllegalStateException(
          "node '" + name + "' runs " + partNodes.size() + " chains, given " + parts.length);
    }
    // this core's chains first (consuming nothing yet), then the others (taken through their
    // toBlock(), which consumes them): a part that fails leaves this core's chains usable
    List<Part<F>> compiled = new ArrayList<>(parts.length);
    for (int i = 0; i < parts.length; i++) {
      compiled.add(ownPart(parts[i], partNodes.get(i)));
    }
    F form;
    try {
      for (int i = 0; i < parts.length; i++) {
        if (compiled.get(i) == null) {
          compiled.set(i, part(parts[i], partNodes.get(i), model));
        }
      }
      form = compile(node, logic, compiled);
    } catch (RuntimeException | Error failed) {
      discardParts(compiled, failed);
      throw failed;
    }
    for (Part<F> part : compiled) {
      part.claim();
    }
    return new ModelChain<>(core, name, form, media);
  }

  /**
   * A declaration that took {@code parts} failed: the media takes back the blocks it made of this
   * core's parts ({@link ChainCompiler#discard}), which stay unused, so the declaration can be
   * made again; a part the media could not take back, or whose own {@code toBlock} said it could
   * not undo what it began ({@link ChainAlreadyUsedException} naming it), is consumed. A chain of
   * another core (or of this core in another form), taken through its {@code toBlock()}, is given
   * back to its core the same way ({@link ModelChain#giveBack}).
   */
  private void discardParts(List<Part<F>> parts, Throwable failed) {
    for (Part<F> part : parts) {
      if (part == null) {
        continue;
      }
      if (part.taken() != null) {
        part.taken().giveBack();
        continue;
      }
      if (part.own() == null) {
        continue;
      }
      String chain = part.own().name();
      if (!media.discard(chain, part.form()) || isKept(chain, failed)) {
        part.claim();
      }
    }
  }

  /** Whether {@code failed} says that the media could not undo what it began with {@code chain}. */
  static boolean isKept(String chain, Throwable failed) {
    return failed instanceof ChainAlreadyUsedException used && chain.equals(used.chainName());
  }

  /**
   * A compiled part: its node, its form, this core's chain it is (claimed once the node is
   * compiled; {@code null} for another chain, consumed when taken), the block a generic template
   * calls, and the chain taken through its {@code toBlock()} for it, which a declaration that
   * fails gives back ({@code null} for this core's own, or a chain made by hand).
   */
  private record Part<F>(
      String node, F form, ModelChain<?, ?, ?> own, Block<?, ?> foreign, ModelChain<?, ?, ?> taken) {
    Block<?, ?> block() {
      return own != null ? own.partBlock() : foreign;
    }

    /** Consumes this core's chain, once the node that takes it compiled. */
    void claim() {
      if (own != null) {
        own.claim();
      }
    }
  }

  /** A chain of this core in this media's form as a part (not consumed yet), or {@code null}. */
  private Part<F> ownPart(Chain<?, ?> chain, String node) {
    if (chain.core() == core && chain instanceof ModelChain<?, ?, ?> mine) {
      F form = mine.formOf(media.form());
      if (form != null) {
        return new Part<>(node, form, mine, null, null);
      }
    }
    return null;
  }

  /**
   * A chain given as a part: this core's in this media's form (consumed by {@link Part#claim()}),
   * or any other, taken through its {@link Chain#toBlock()} now and compiled as its node says.
   */
  private Part<F> part(Chain<?, ?> chain, String node, TopologyRecorder model) {
    Part<F> own = ownPart(chain, node);
    if (own != null) {
      return own;
    }
    // another core's chain (recorded as a ForeignChain whose logic is that chain), or a chain of
    // this core that is not in this media's form: taken through its toBlock()
    NodeLogic logic = model.logic(node);
    Chain<?, ?> other = logic instanceof NodeLogic.OtherChain foreign ? foreign.chain() : chain;
    Block<?, ?> block = other.toBlock();
    ModelChain<?, ?, ?> taken = other instanceof ModelChain<?, ?, ?> chainOfACore ? chainOfACore : null;
    try {
      TopologyNode partNode = model.node(node);
      if (partNode instanceof TopologyNode.ForeignChain) { // this core's own chains are metered
        block = metered(partNode, block);
      }
      return new Part<>(node, media.foreign(node, block), null, block, taken);
    } catch (RuntimeException | Error failed) {
      if (taken != null) {
        taken.giveBack();
      }
      throw failed;
    }
  }

  /**
   * The names of the chains a chain node is given, in the order its recorder was given them: its
   * parts, except for the nodes whose part is a source (collectors) or a block they share (isolate's
   * users), which are given no chain.
   */
  private static List<String> chainParts(TopologyNode node) {
    if (node instanceof TopologyNode.SyncCollector
        || node instanceof TopologyNode.AsyncCollector
        || node instanceof TopologyNode.IsolatedUser) {
      return List.of();
    }
    return node.parts().stream().map(TopologyNode.Part::node).toList();
  }

  private F compile(TopologyNode node, NodeLogic logic, List<Part<F>> parts) {
    String name = node.name();
    if (logic instanceof NodeLogic.Run run) {
      return media.block(name, metered(node, recorded(node, run.block())));
    }
    if (logic instanceof NodeLogic.Shared shared) {
      return media.block(name, metered(node, shared.block()));
    }
    if (node instanceof TopologyNode.SyncCollector) {
      return media.block(name, metered(node, syncCollector(((NodeLogic.Collect) logic).source())));
    }
    if (node instanceof TopologyNode.AsyncCollector) {
      return media.block(
          name, metered(node, asyncCollector(((NodeLogic.Collect) logic).source())));
    }
    if (node instanceof TopologyNode.Repeater) {
      return media.block(name, metered(node, repeater((NodeLogic.Repeat) logic, parts)));
    }
    List<F> forms = new ArrayList<>(parts.size());
    for (Part<F> part : parts) {
      forms.add(part.form());
    }
    // a metered template runs as the generic block with its tap (a link is not metered: it is
    // the media's to compile, and its parts are metered)
    F own =
        metering == null || node instanceof TopologyNode.Link
            ? media.template(node, logic, forms)
            : null;
    return own != null ? own : media.block(name, metered(node, generic(node, logic, parts)));
  }

  /** A chain node's block, with a metering tap if metrics are on (never a link's). */
  private Block<?, ?> metered(TopologyNode node, Block<?, ?> block) {
    return metering == null || node instanceof TopologyNode.Link
        ? block
        : metering.chain(node, block);
  }

  /** A chain's block, with a recording tap if recording is on and the node is recorded. */
  private Block<?, ?> recorded(TopologyNode node, Block<?, ?> block) {
    return recording != null && node instanceof TopologyNode.BlockChain
        ? recording.chain(node.name(), block)
        : block;
  }

  /**
   * A sync collector's block: on a media that carries calls between processes, its wait also ends
   * when the caller gave up ({@link PrimeCore#callerGaveUp}).
   */
  private <T> Block<Token, T> syncCollector(Source<T> source) {
    Reader<T> reader = collectorReader(source);
    return new SyncCollectorBlock<>(
        reader, callersMayBeElsewhere() ? core::callerGaveUp : null, core::ensureOpen);
  }

  /**
   * The reader of a collector of {@code source}. One of another core's sources stays open when
   * this core closes, so the reader is closed with this core: a wait in it ends then, and the
   * collector, finding its reader closed, says that its core is.
   */
  private <T> Reader<T> collectorReader(Source<T> source) {
    Reader<T> reader = InProcessServices.serviceReader(source);
    if (source.core() != core) {
      memory.closeOnClose(reader);
    }
    return reader;
  }

  /**
   * Whether a block of this media may run on a service's thread for a caller in another process,
   * who may give up meanwhile: a media that carries values between processes (and so copies them).
   */
  private boolean callersMayBeElsewhere() {
    return media.copiesValues();
  }

  private <T> Block<Token, List<T>> asyncCollector(Source<T> source) {
    return new AsyncCollectorBlock<>(collectorReader(source), core::ensureOpen);
  }

  @SuppressWarnings({"unchecked", "rawtypes"})
  private Block<?, ?> repeater(NodeLogic.Repeat logic, List<Part<F>> parts) {
    Block collector = parts.size() > 1 ? parts.get(1).block() : null;
    return new RepeaterLoopBlock(
        parts.get(0).block(),
        collector,
        logic.repeater(),
        core::ensureOpen,
        callersMayBeElsewhere() ? core::callerGaveUp : null);
  }

  /** The generic block of a template, calling its parts' blocks. */
  @SuppressWarnings({"unchecked", "rawtypes"})
  private static Block<?, ?> generic(TopologyNode node, NodeLogic logic, List<? extends Part<?>> p) {
    if (node instanceof TopologyNode.Link) {
      return new LinkBlock(p.get(0).block(), p.get(1).block());
    }
    if (node instanceof TopologyNode.IfElse) {
      return new IfThenElseBlock(
          ((NodeLogic.Condition) logic).condition(), p.get(0).block(), p.get(1).block());
    }
    if (node instanceof TopologyNode.ForEach) {
      return new ForEachBlock(p.get(0).block());
    }
    if (node instanceof TopologyNode.Fork) {
      return new ForkBlock(p.get(0).block(), ((NodeLogic.Events) logic).events());
    }
    if (node instanceof TopologyNode.Guard) {
      NodeLogic.Guarded guarded = (NodeLogic.Guarded) logic;
      return new GuardBlock(guarded.pass(), p.get(0).block(), guarded.substitute());
    }
    if (node instanceof TopologyNode.Union) {
      Block[] b = new Block[p.size()];
      for (int i = 0; i < b.length; i++) {
        b[i] = p.get(i).block();
      }
      switch (b.length) {
        case 2:
          return UnionBlock.of(b[0], b[1]);
        case 3:
          return UnionBlock.of(b[0], b[1], b[2]);
        case 4:
          return UnionBlock.of(b[0], b[1], b[2], b[3]);
        default:
          return UnionBlock.of(b[0], b[1], b[2], b[3], b[4]);
      }
    }
    throw new IllegalStateException("not a chain template: " + node);
  }
}

package dev.prime;

import dev.prime.internal.Names;
import dev.prime.topology.Topology;
import dev.prime.topology.TopologyNode;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.Collections;
import java.util.LinkedHashSet;
import java.util.Set;
import java.util.HashMap;
import java.util.List;
import java.util.Map;
import java.util.Objects;
import java.util.function.Consumer;
import java.util.function.Predicate;
import java.util.function.Supplier;

/**
 * Records the diagram declared on one core as {@link TopologyNode}s, and makes every name: the one
 * place where chains, sources and template chains get their names ({@code a>b}, {@code
 * if(a|b)}, {@code guard(a)}, ...). Every media names what it builds through this class, so the
 * same declarations give the same names, Redis keys and log names on every media.
 *
 * <p>Each method records one node and returns its name. A chain or source of another core used
 * here is recorded first as a {@link TopologyNode.ForeignChain} ({@code hosted(name)}) or {@link
 * TopologyNode.ForeignSource}, whose name is then the part's name. {@link PrimeCore} makes one
 * per core ({@link PrimeCore#topologyRecorder()} gives it to media). Thread-safe.
 *
 * <p>Each node is recorded with its {@link NodeLogic} (the block, predicate, event block, source
 * or other core's chain it runs), which the public {@link TopologyNode} leaves out: a media
 * compiles a node from the node and {@link #logic(String) its logic} (see {@link
 * ChainCompiler}), so the model is the one description of the diagram every media compiles.
 *
 * <p>Design note (threading). Every method synchronises on the recorder; {@link #declare} holds
 * that monitor for a whole declaration (checks, recording, compiling and consuming the parts), so
 * two declarations of one core never interleave, and a declaration made inside another (a
 * repeater's collector) joins it (the monitor is reentrant). A declaration that throws forgets
 * the nodes it recorded and releases their names; one that succeeds releases their logic, so the
 * recorder holds the user's blocks only while they are compiled. Snapshots ({@link #snapshot},
 * {@link #hostedServices}) never wait for a declaration under way (a media's may wait for Redis or
 * another process's lease): whenever no declaration is under way, what is recorded is published
 * as an immutable {@link Published} view, which readers on other threads take without the
 * monitor, so they see every finished declaration and nothing of one under way (it may still be
 * forgotten). {@link PrimeCore#start()} is no such reader: it takes the monitor as it marks the
 * core started, so a declaration under way, which saw the core not started and left its services
 * to the start, has ended and is seen by it. The thread that declares sees its declaration's
 * nodes (it holds the monitor). Nodes
 * are only appended, and a failed declaration forgets only nodes never published, so the view
 * shares one append-only array: publishing costs the nodes added, not the whole diagram. Nothing
 * here waits for another thread while holding the monitor, except what a media's compiler does in
 * a declaration.
 */
final class TopologyRecorder {
  private final PrimeCore owner;
  private final Names names = new Names();
  private final List<TopologyNode> nodes = new ArrayList<>(); // guarded by this
  private final Map<String, TopologyNode> byName = new HashMap<>(); // guarded by this
  private final Map<String, NodeLogic> logic = new HashMap<>(); // guarded by this
  private final Map<Object, String> foreign = new HashMap<>(); // guarded by this
  private final Map<String, Integer> readers = new HashMap<>(); // guarded by this
  private final Map<String, String> pseudonames = new HashMap<>(); // guarded by this

  /** How many declarations this thread is inside (nested ones join): publishing waits for 0. */
  private int declaring; // guarded by this

  /** The published nodes, in order: only appended to, and never changed below the published size. */
  private TopologyNode[] shelf = new TopologyNode[16]; // guarded by this

  /** What was recorded when no declaration was under way, for readers that must not wait. */
  private volatile Published published = new Published(shelf, 0, Map.of());

  /**
   * An immutable view of the recorded nodes: the first {@code size} of {@code nodes} (never
   * changed once published) and the pseudonames.
   */
  private record Published(TopologyNode[] nodes, int size, Map<String, String> pseudonames) {
    List<TopologyNode> list() {
      return Collections.unmodifiableList(Arrays.asList(nodes).subList(0, size));
    }
  }

  /**
   * @param owner the core whose diagram this records
   */
  TopologyRecorder(PrimeCore owner) {
    this.owner = Objects.requireNonNull(owner, "owner");
  }

  /**
   * Records a chain made of a block.
   *
   * @param name the name the user gave, or {@code null} for {@code chain-N}
   * @param block the chain's block
   * @return the claimed name
   * @throws IllegalArgumentException if the name is invalid or taken
   */
  synchronized String blockChain(String name, Block<?, ?> block) {
    NodeLogic run = new NodeLogic.Run(block);
    return add(
        new TopologyNode.BlockChain(name == null ? names.fresh("chain") : names.claim(name)), run);
  }

  /**
   * Records a source fed by an event block.
   *
   * @param name the name the user gave, or {@code null} for {@code source-N}
   * @param events what the source publishes
   * @return the claimed name
   * @throws IllegalArgumentException if the name is invalid or taken
   */
  synchronized String eventSource(String name, EventBlock<?> events) {
    NodeLogic published = new NodeLogic.Events(events);
    return add(
        new TopologyNode.EventSource(name == null ? names.fresh("source") : names.claim(name)),
        published);
  }

  /**
   * Records two linked chains.
   *
   * @param first runs first
   * @param second runs on its outputs
   * @return the linked chain's name, {@code first>second}
   */
  synchronized String link(Chain<?, ?> first, Chain<?, ?> second) {
    String a = part(first);
    String b = part(second);
    return add(
        new TopologyNode.Link(names.derived(first.name() + ">" + second.name(), "link"), a, b),
        NodeLogic.None.NONE);
  }

  /**
   * Records the if/else template.
   *
   * @param then the chain for inputs that satisfy the condition
   * @param otherwise the chain for the others
   * @param condition chooses the branch
   * @return the template chain's name, {@code if(then|otherwise)}
   */
  synchronized String ifElse(
      Chain<?, ?> then, Chain<?, ?> otherwise, Predicate<?> condition) {
    NodeLogic chooses = new NodeLogic.Condition(condition);
    String a = part(then);
    String b = part(otherwise);
    String name = names.derived("if(" + then.name() + "|" + otherwise.name() + ")", "if");
    return add(new TopologyNode.IfElse(name, a, b), chooses);
  }

  /**
   * Records the for-each template.
   *
   * @param body the chain for one element
   * @return the template chain's name, {@code forEach(body)}
   */
  synchronized String forEach(Chain<?, ?> body) {
    String b = part(body);
    return add(
        new TopologyNode.ForEach(names.derived("forEach(" + body.name() + ")", "forEach"), b),
        NodeLogic.None.NONE);
  }

  /**
   * Records a union of 2 to 5 chains.
   *
   * @param chains the chains, in tuple order
   * @return the template chain's name, {@code union(a|b|...)}
   */
  synchronized String union(Chain<?, ?>... chains) {
    List<String> parts = new ArrayList<>(chains.length);
    StringBuilder preferred = new StringBuilder("union(");
    for (int i = 0; i < chains.length; i++) {
      parts.add(part(chains[i]));
      preferred.append(i == 0 ? "" : "|").append(chains[i].name());
    }
    String name = names.derived(preferred.append(')').toString(), "union");
    return add(new TopologyNode.Union(name, parts), NodeLogic.None.NONE);
  }

  /**
   * Records the fork template.
   *
   * @param chain the forked chain
   * @param events receives every output
   * @return the template chain's name, {@code fork(chain)}
   */
  synchronized String fork(Chain<?, ?> chain, EventBlock<?> events) {
    NodeLogic publishes = new NodeLogic.Events(events);
    String c = part(chain);
    return add(
        new TopologyNode.Fork(names.derived("fork(" + chain.name() + ")", "fork"), c), publishes);
  }

  /**
   * Records the guard template.
   *
   * @param chain the guarded chain
   * @param pass decides which inputs run the chain
   * @param substitute the output for the others
   * @return the template chain's name, {@code guard(chain)}
   */
  synchronized String guard(
      Chain<?, ?> chain, Predicate<?> pass, Block<?, ?> substitute) {
    NodeLogic guarded = new NodeLogic.Guarded(pass, substitute);
    String c = part(chain);
    return add(
        new TopologyNode.Guard(names.derived("guard(" + chain.name() + ")", "guard"), c), guarded);
  }

  /**
   * Records that a chain is shared by isolation (no node of its own: its users are the nodes).
   *
   * @param chain the shared chain
   * @return the name of the shared chain's node
   */
  synchronized String isolate(Chain<?, ?> chain) {
    return part(chain);
  }

  /**
   * Records one user of an isolated chain.
   *
   * @param shared the shared chain's node, from {@link #isolate}
   * @param sharedName the shared chain's own name
   * @param user 1 for the first user, 2 for the next, ...
   * @param block the block every user calls, which runs the shared chain one call at a time
   * @return the user chain's name, {@code shared@user}
   */
  synchronized String isolatedUser(
      String shared, String sharedName, int user, Block<?, ?> block) {
    NodeLogic calls = new NodeLogic.Shared(block);
    return add(
        new TopologyNode.IsolatedUser(names.derived(sharedName + "@" + user, "isolated"), shared),
        calls);
  }

  /**
   * Records a sync collector.
   *
   * @param source the source it reads
   * @return the collector chain's name, {@code collect(source)}
   */
  synchronized String syncCollector(Source<?> source) {
    String s = sourcePart(source);
    return add(
        new TopologyNode.SyncCollector(
            names.derived("collect(" + source.name() + ")", "collect"), s),
        new NodeLogic.Collect(source));
  }

  /**
   * Records an async collector.
   *
   * @param source the source it reads
   * @return the collector chain's name, {@code collectAll(source)}
   */
  synchronized String asyncCollector(Source<?> source) {
    String s = sourcePart(source);
    return add(
        new TopologyNode.AsyncCollector(
            names.derived("collectAll(" + source.name() + ")", "collectAll"), s),
        new NodeLogic.Collect(source));
  }

  /**
   * Records a repeater.
   *
   * @param inner the chain run each round
   * @param collector the async collector it reads between rounds (recorded before), or {@code
   *     null}
   * @param repeater decides after each round
   * @return the repeater chain's name, {@code repeat(inner)}
   */
  synchronized String repeater(
      Chain<?, ?> inner, String collector, RepeaterBlock<?, ?, ?, ?> repeater) {
    NodeLogic decides = new NodeLogic.Repeat(repeater);
    String i = part(inner);
    return add(
        new TopologyNode.Repeater(
            names.derived("repeat(" + inner.name() + ")", "repeat"), i, collector),
        decides);
  }

  /**
   * Records a chain linked to a source.
   *
   * @param source the input source
   * @param chain the chain that runs on it
   * @return the output source's name, {@code source>chain}
   */
  synchronized String sourceLink(Source<?> source, Chain<?, ?> chain) {
    String s = sourcePart(source);
    String c = part(chain);
    return add(
        new TopologyNode.SourceLink(
            names.derived(source.name() + ">" + chain.name(), "link"), s, c),
        NodeLogic.None.NONE);
  }

  /**
   * Records a filter of a source.
   *
   * @param source the input source
   * @param predicate decides which values pass
   * @return the filtered source's name, {@code filter(source)}
   */
  synchronized String filter(Source<?> source, Predicate<?> predicate) {
    NodeLogic passes = new NodeLogic.Condition(predicate);
    String s = sourcePart(source);
    return add(
        new TopologyNode.Filter(names.derived("filter(" + source.name() + ")", "filter"), s),
        passes);
  }

  /**
   * Records a flat-map of a source.
   *
   * @param source the input source
   * @param block makes the values published for each input
   * @return the flattened source's name, {@code flatMap(source)}
   */
  synchronized String flatMap(Source<?> source, Block<?, ? extends Iterable<?>> block) {
    NodeLogic expands = new NodeLogic.Expand(block);
    String s = sourcePart(source);
    return add(
        new TopologyNode.FlatMap(names.derived("flatMap(" + source.name() + ")", "flatMap"), s),
        expands);
  }

  /**
   * Records a listener of a source.
   *
   * @param source the source
   * @param listener called with every value
   * @return the listener's name, {@code listen(source)}
   */
  synchronized String listener(Source<?> source, Consumer<?> listener) {
    NodeLogic listens = new NodeLogic.Listen(listener);
    String s = sourcePart(source);
    return add(
        new TopologyNode.Listener(names.derived("listen(" + source.name() + ")", "listen"), s),
        listens);
  }

  /**
   * Records a generic service.
   *
   * @param name the name the user gave
   * @param service what it runs
   * @return the claimed name
   * @throws IllegalArgumentException if the name is invalid or taken
   */
  synchronized String genericService(String name, GenericService service) {
    NodeLogic works = new NodeLogic.Work(service);
    return add(new TopologyNode.GenericServiceNode(names.claim(name)), works);
  }

  /**
   * Records a combinator of sources: {@code combineLatest}, {@code zip}, {@code merge}, {@code
   * withLatestFrom} or {@code sample}.
   *
   * @param kind which combinator
   * @param sources its inputs, in order
   * @return the output source's name, {@code kind(a|b|...)}
   */
  synchronized String combinator(String kind, List<? extends Source<?>> sources) {
    List<String> parts = new ArrayList<>(sources.size());
    StringBuilder preferred = new StringBuilder(kind).append('(');
    for (int i = 0; i < sources.size(); i++) {
      parts.add(sourcePart(sources.get(i)));
      preferred.append(i == 0 ? "" : "|").append(sources.get(i).name());
    }
    String name = names.derived(preferred.append(')').toString(), kind);
    return add(new TopologyNode.Combinator(name, kind, parts), NodeLogic.None.NONE);
  }

  /**
   * Records a timer.
   *
   * @param name the name the user gave
   * @param period its period
   * @return the claimed name
   * @throws IllegalArgumentException if the name is invalid or taken
   */
  synchronized String timer(String name, java.time.Duration period) {
    return add(new TopologyNode.Timer(names.claim(name), period), NodeLogic.None.NONE);
  }

  /**
   * Records a reader the program opened on a source of this core.
   *
   * @param source the source's name
   */
  synchronized void reader(String source) {
    if (!byName.containsKey(source)) {
      throw new IllegalStateException("no source named '" + source + "' was recorded");
    }
    add(
        new TopologyNode.ReaderNode(source, readers.merge(source, 1, Integer::sum)),
        NodeLogic.None.NONE);
  }

  /**
   * Claims a name derived from others for something that is not a node of the diagram (it is
   * still unique among the core's names). Names of the diagram's nodes come from the recording
   * methods.
   *
   * @param preferred the derived name
   * @param kind the fallback prefix if it is too long or invalid ({@code kind-N})
   * @return a unique name
   */
  synchronized String derived(String preferred, String kind) {
    return names.derived(preferred, kind);
  }

  /**
   * The node with a name.
   *
   * @param name a recorded name
   * @return the node
   * @throws IllegalArgumentException if nothing of that name was recorded
   */
  synchronized TopologyNode node(String name) {
    TopologyNode node = byName.get(name);
    if (node == null) {
      throw new IllegalArgumentException("nothing named '" + name + "' was recorded");
    }
    return node;
  }

  /**
   * The logic of the node with a name: what a media needs, besides the node, to compile it. It
   * is kept only while the declaration that recorded the node runs ({@link #declare}): the node
   * is compiled then, and another core's chain is consumed then.
   *
   * @param name a recorded name
   * @return the node's logic
   * @throws IllegalArgumentException if nothing of that name was recorded
   * @throws IllegalStateException if the node was compiled and its logic released
   */
  synchronized NodeLogic logic(String name) {
    node(name);
    NodeLogic kept = logic.get(name);
    if (kept == null) {
      throw new IllegalStateException(
          "the logic of '" + name + "' was released once its declaration compiled it; a media"
              + " compiles a node from the logic it is given while the node is declared");
    }
    return kept;
  }

  /**
   * Runs one declaration (a link, template or service: its checks, the nodes it records and the
   * chains it consumes) atomically: declarations of this core run one at a time (a declaration
   * made inside another joins it), and if {@code declaration} throws, every node recorded during
   * it is forgotten and its name released, so a failed declaration leaves no node behind. Once
   * it succeeded, the logic of the nodes it recorded is released ({@link #logic}): the media
   * compiled them, and the recorder must not keep the user's blocks alive for the core's
   * lifetime.
   *
   * @param declaration checks, records and compiles
   * @param <T> what it makes
   * @return what it made
   */
  synchronized <T> T declare(Supplier<T> declaration) {
    owner.ensureStartDidNotFail("a declaration");
    int mark = nodes.size();
    T made;
    declaring++;
    try {
      made = declaration.get();
    } catch (RuntimeException | Error e) {
      forgetSince(mark);
      throw e;
    } finally {
      declaring--;
      publish();
    }
    for (int i = mark; i < nodes.size(); i++) {
      logic.remove(nodes.get(i).name());
    }
    return made;
  }

  /**
   * Publishes what is recorded for readers that must not wait ({@link #view}), unless a
   * declaration is under way: that one publishes when it ends.
   */
  private void publish() {
    if (declaring > 0) {
      return;
    }
    Published last = published;
    int size = nodes.size();
    if (size < last.size()) {
      throw new IllegalStateException(
          "published nodes were forgotten: " + size + " recorded, " + last.size() + " published");
    }
    if (size > shelf.length) {
      shelf = Arrays.copyOf(shelf, Math.max(size, shelf.length * 2));
    }
    for (int i = last.size(); i < size; i++) {
      shelf[i] = nodes.get(i);
    }
    Map<String, String> names =
        last.pseudonames().equals(pseudonames) ? last.pseudonames() : Map.copyOf(pseudonames);
    published = new Published(shelf, size, names);
  }

  /**
   * What a snapshot shows: on the thread that holds the monitor (a declaration under way, whose
   * media reads the topology it declares), what is recorded now; on any other thread, what was
   * published, without waiting for a declaration under way.
   */
  private Published view() {
    if (Thread.holdsLock(this)) {
      TopologyNode[] now = nodes.toArray(new TopologyNode[0]);
      return new Published(now, now.length, Map.copyOf(pseudonames));
    }
    return published;
  }

  /** Forgets the nodes recorded after the first {@code mark}, latest first. */
  private void forgetSince(int mark) {
    for (int i = nodes.size() - 1; i >= mark; i--) {
      TopologyNode node = nodes.remove(i);
      String name = node.name();
      byName.remove(name);
      logic.remove(name);
      if (node instanceof TopologyNode.ReaderNode reader) {
        readers.merge(reader.source(), -1, Integer::sum); // a reader's name is not claimed
      } else {
        foreign.values().remove(name);
        pseudonames.remove(name);
        names.release(name);
      }
    }
  }

  /**
   * Gives a recorded chain or source a pseudoname: a readable name for drawings and recordings
   * (see {@link #checkPseudoname}).
   *
   * @param name a recorded node's name
   * @param pseudoname the readable name, checked
   */
  synchronized void pseudoname(String name, String pseudoname) {
    node(name);
    pseudonames.put(name, checkPseudoname(pseudoname));
    publish();
  }

  /**
   * The pseudoname of a node.
   *
   * @param name a node's name
   * @return its pseudoname, or {@code null} if it has none
   */
  synchronized String pseudoname(String name) {
    return pseudonames.get(name);
  }

  /**
   * Checks a pseudoname before anything is recorded with it: 1 to 120 characters, not only
   * whitespace, no control characters.
   *
   * @param pseudoname the readable name
   * @return it
   * @throws IllegalArgumentException if it is not a valid pseudoname
   */
  static String checkPseudoname(String pseudoname) {
    Objects.requireNonNull(pseudoname, "pseudoname must not be null");
    boolean control = pseudoname.chars().anyMatch(Character::isISOControl);
    if (pseudoname.isBlank() || pseudoname.length() > 120 || control) {
      throw new IllegalArgumentException(
          "pseudoname '" + pseudoname + "' is invalid: use 1 to 120 characters, not only"
              + " whitespace, without control characters (line breaks, tabs)");
    }
    return pseudoname;
  }

  /**
   * A snapshot of what was recorded: every finished declaration, never one under way on another
   * thread (see the design note: it does not wait for it).
   *
   * @param hostedHere whether this process runs a service
   * @return the topology
   */
  Topology snapshot(Predicate<String> hostedHere) {
    Published view = view();
    List<TopologyNode> recorded = view.list();
    List<String> elsewhere = new ArrayList<>();
    for (TopologyNode node : recorded) {
      if (node.isService() && !hostedHere.test(node.name())) {
        elsewhere.add(node.name());
      }
    }
    return Topology.of(recorded, elsewhere, view.pseudonames());
  }

  /**
   * The services this process runs, in declaration order ({@link PrimeCore#serviceNames()}).
   *
   * @param hostedHere whether this process runs a service
   * @return an unmodifiable set
   */
  Set<String> hostedServices(Predicate<String> hostedHere) {
    Set<String> hosted = new LinkedHashSet<>();
    for (TopologyNode node : view().list()) {
      if (node.isService() && hostedHere.test(node.name())) {
        hosted.add(node.name());
      }
    }
    return Collections.unmodifiableSet(hosted);
  }

  private String add(TopologyNode node, NodeLogic runs) {
    nodes.add(node);
    byName.put(node.name(), node);
    logic.put(node.name(), runs);
    publish();
    return node.name();
  }

  /**
   * The node of a chain or source whose {@code core()} is the owning core: recorded when the core
   * made it; anything else is an implementation of {@link Chain} or {@link Source} of the user's
   * own, which the core cannot compile.
   */
  private String own(String name, String kind, String maker) {
    if (!byName.containsKey(name)) {
      throw new IllegalArgumentException(
          "the " + kind + " '" + name + "' says it belongs to core '" + owner.name() + "' but was"
              + " not made by this core's " + maker + ": a " + kind + " of your own implementation"
              + " cannot be linked. Make it with core." + maker + " and give it your logic"
              + ("chain".equals(kind) ? " as a Block" : " through an EventBlock"));
    }
    return name;
  }

  /** The node name of a chain used as a part: its own, or a new foreign node's. */
  private String part(Chain<?, ?> chain) {
    if (chain.core() == owner) {
      return own(chain.name(), "chain", "chain(name, block)");
    }
    String known = foreign.get(chain);
    if (known != null && logic.containsKey(known)) {
      return known; // given again in the declaration that recorded it
    }
    String name = names.derived("hosted(" + chain.name() + ")", "hosted");
    foreign.put(chain, name);
    return add(
        new TopologyNode.ForeignChain(name, chain.core().name(), chain.name()),
        new NodeLogic.OtherChain(chain));
  }

  /** The node name of a source used as a part: its own, or a new foreign node's. */
  private String sourcePart(Source<?> source) {
    if (source.core() == owner) {
      return own(source.name(), "source", "source(name, events)");
    }
    String known = foreign.get(source);
    if (known != null) {
      return known;
    }
    String name =
        names.derived("from(" + source.core().name() + ":" + source.name() + ")", "foreign");
    foreign.put(source, name);
    return add(
        new TopologyNode.ForeignSource(name, source.core().name(), source.name()),
        new NodeLogic.OtherSource(source));
  }
}

package dev.prime.topology;

import java.util.List;
import java.util.Objects;

/**
 * One element of a {@link Topology}: a chain, a source, a service of a source or a reader, with
 * its name and the nodes it is made of or reads ({@link #parts()}). Nodes are immutable and refer
 * to other nodes by name; a part is always declared before the node that uses it.
 *
 * <p>Which nodes are <em>services</em> ({@link #isService()}): the places where a block of the
 * diagram runs. Every chain made of a block, every template chain (if/else, for-each, union, fork,
 * guard, each user of an isolated chain, the collectors, the repeater), every chain of another
 * core used here, every filter, flat-map and listener of a source, every generic service
 * ({@code core.service(name, service)}), every combinator of sources and every timer. Links are
 * not services:
 * a linked chain is made of the services of its parts. Sources and readers are not services
 * either: a source is a stream that services publish to.
 */
public sealed interface TopologyNode
    permits TopologyNode.BlockChain,
        TopologyNode.ForeignChain,
        TopologyNode.Link,
        TopologyNode.IfElse,
        TopologyNode.ForEach,
        TopologyNode.Union,
        TopologyNode.Fork,
        TopologyNode.Guard,
        TopologyNode.IsolatedUser,
        TopologyNode.SyncCollector,
        TopologyNode.AsyncCollector,
        TopologyNode.Repeater,
        TopologyNode.EventSource,
        TopologyNode.ForeignSource,
        TopologyNode.SourceLink,
        TopologyNode.Filter,
        TopologyNode.FlatMap,
        TopologyNode.Listener,
        TopologyNode.ReaderNode,
        TopologyNode.GenericServiceNode,
        TopologyNode.Combinator,
        TopologyNode.Timer {

  /** {@return the node's name: unique among the nodes of a topology} */
  String name();

  /** {@return the nodes this node is made of or reads, in a fixed order} */
  List<Part> parts();

  /** {@return whether this node is a service (see the interface's docs)} */
  boolean isService();

  /** {@return whether this node is a chain (values go in and come out), as opposed to a source} */
  boolean isChain();

  /**
   * A node used by another.
   *
   * @param role what the part is to the node that uses it ({@code then}, {@code body}, ...)
   * @param node the part's name
   * @param flow how the node uses it
   */
  record Part(String role, String node, Flow flow) {
    /**
     * Checks the components.
     *
     * @param role what the part is to the node that uses it ({@code then}, {@code body}, ...)
     * @param node the part's name
     * @param flow how the node uses it
     */
    public Part {
      Objects.requireNonNull(role, "role");
      Objects.requireNonNull(node, "node");
      Objects.requireNonNull(flow, "flow");
    }
  }

  /** How a node uses one of its parts. */
  enum Flow {
    /** The part's values flow into the node (a source and its reader, a link's parts). */
    READS,
    /** The node runs the part as a chain of its own (a template and the chains it was given). */
    RUNS
  }

  /**
   * A chain made of a user's block ({@code core.chain(block)}).
   *
   * @param name the chain's name
   */
  record BlockChain(String name) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name the chain's name
     */
    public BlockChain {
      Objects.requireNonNull(name, "name");
    }

    @Override
    public List<Part> parts() {
      return List.of();
    }

    @Override
    public boolean isService() {
      return true;
    }

    @Override
    public boolean isChain() {
      return true;
    }
  }

  /**
   * A chain of another core used in this one: run here through its block.
   *
   * @param name its name in this topology
   * @param core the core it belongs to
   * @param chain its name in that core
   */
  record ForeignChain(String name, String core, String chain) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name its name in this topology
     * @param core the core it belongs to
     * @param chain its name in that core
     */
    public ForeignChain {
      Objects.requireNonNull(name, "name");
      Objects.requireNonNull(core, "core");
      Objects.requireNonNull(chain, "chain");
    }

    @Override
    public List<Part> parts() {
      return List.of();
    }

    @Override
    public boolean isService() {
      return true;
    }

    @Override
    public boolean isChain() {
      return true;
    }
  }

  /**
   * Two chains linked: the first's outputs are the second's inputs.
   *
   * @param name the linked chain's name ({@code first>second})
   * @param first runs first
   * @param second runs on the first's outputs
   */
  record Link(String name, String first, String second) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name the linked chain's name ({@code first>second})
     * @param first runs first
     * @param second runs on the first's outputs
     */
    public Link {
      Objects.requireNonNull(name, "name");
      Objects.requireNonNull(first, "first");
      Objects.requireNonNull(second, "second");
    }

    @Override
    public List<Part> parts() {
      return List.of(new Part("first", first, Flow.READS), new Part("second", second, Flow.READS));
    }

    @Override
    public boolean isService() {
      return false;
    }

    @Override
    public boolean isChain() {
      return true;
    }
  }

  /**
   * The if/else template: runs {@code then} or {@code otherwise}, chosen per input.
   *
   * @param name the template chain's name
   * @param then the chain for inputs that satisfy the condition
   * @param otherwise the chain for the others
   */
  record IfElse(String name, String then, String otherwise) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name the template chain's name
     * @param then the chain for inputs that satisfy the condition
     * @param otherwise the chain for the others
     */
    public IfElse {
      Objects.requireNonNull(name, "name");
      Objects.requireNonNull(then, "then");
      Objects.requireNonNull(otherwise, "otherwise");
    }

    @Override
    public List<Part> parts() {
      return List.of(new Part("then", then, Flow.RUNS), new Part("else", otherwise, Flow.RUNS));
    }

    @Override
    public boolean isService() {
      return true;
    }

    @Override
    public boolean isChain() {
      return true;
    }
  }

  /**
   * The for-each template: runs {@code body} on each element of a list.
   *
   * @param name the template chain's name
   * @param body the chain for one element
   */
  record ForEach(String name, String body) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name the template chain's name
     * @param body the chain for one element
     */
    public ForEach {
      Objects.requireNonNull(name, "name");
      Objects.requireNonNull(body, "body");
    }

    @Override
    public List<Part> parts() {
      return List.of(new Part("body", body, Flow.RUNS));
    }

    @Override
    public boolean isService() {
      return true;
    }

    @Override
    public boolean isChain() {
      return true;
    }
  }

  /**
   * The union template: gives each input to 2 to 5 chains and returns their outputs.
   *
   * @param name the template chain's name
   * @param chains the chains, in tuple order
   */
  record Union(String name, List<String> chains) implements TopologyNode {
    /**
     * Checks the components and copies the list.
     *
     * @param name the template chain's name
     * @param chains the chains, in tuple order
     */
    public Union {
      Objects.requireNonNull(name, "name");
      chains = List.copyOf(chains);
      if (chains.size() < 2 || chains.size() > 5) {
        throw new IllegalArgumentException("a union has 2 to 5 chains, not " + chains.size());
      }
    }

    @Override
    public List<Part> parts() {
      Part[] parts = new Part[chains.size()];
      for (int i = 0; i < parts.length; i++) {
        parts[i] = new Part(String.valueOf(i + 1), chains.get(i), Flow.RUNS);
      }
      return List.of(parts);
    }

    @Override
    public boolean isService() {
      return true;
    }

    @Override
    public boolean isChain() {
      return true;
    }
  }

  /**
   * The fork template: runs {@code chain} and also publishes each output to an event block.
   *
   * @param name the template chain's name
   * @param chain the forked chain
   */
  record Fork(String name, String chain) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name the template chain's name
     * @param chain the forked chain
     */
    public Fork {
      Objects.requireNonNull(name, "name");
      Objects.requireNonNull(chain, "chain");
    }

    @Override
    public List<Part> parts() {
      return List.of(new Part("chain", chain, Flow.RUNS));
    }

    @Override
    public boolean isService() {
      return true;
    }

    @Override
    public boolean isChain() {
      return true;
    }
  }

  /**
   * The guard template: runs {@code chain} for inputs that pass, a substitute for the others.
   *
   * @param name the template chain's name
   * @param chain the guarded chain
   */
  record Guard(String name, String chain) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name the template chain's name
     * @param chain the guarded chain
     */
    public Guard {
      Objects.requireNonNull(name, "name");
      Objects.requireNonNull(chain, "chain");
    }

    @Override
    public List<Part> parts() {
      return List.of(new Part("chain", chain, Flow.RUNS));
    }

    @Override
    public boolean isService() {
      return true;
    }

    @Override
    public boolean isChain() {
      return true;
    }
  }

  /**
   * One user of an isolated chain ({@code isolate(shared).newUser()}); every user runs the same
   * shared chain, never two at once.
   *
   * @param name the user chain's name ({@code shared@n})
   * @param shared the shared chain
   */
  record IsolatedUser(String name, String shared) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name the user chain's name ({@code shared@n})
     * @param shared the shared chain
     */
    public IsolatedUser {
      Objects.requireNonNull(name, "name");
      Objects.requireNonNull(shared, "shared");
    }

    @Override
    public List<Part> parts() {
      return List.of(new Part("shared", shared, Flow.RUNS));
    }

    @Override
    public boolean isService() {
      return true;
    }

    @Override
    public boolean isChain() {
      return true;
    }
  }

  /**
   * The sync collector: a chain that returns the next value of {@code source} on each call.
   *
   * @param name the collector chain's name
   * @param source the source it reads
   */
  record SyncCollector(String name, String source) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name the collector chain's name
     * @param source the source it reads
     */
    public SyncCollector {
      Objects.requireNonNull(name, "name");
      Objects.requireNonNull(source, "source");
    }

    @Override
    public List<Part> parts() {
      return List.of(new Part("source", source, Flow.READS));
    }

    @Override
    public boolean isService() {
      return true;
    }

    @Override
    public boolean isChain() {
      return true;
    }
  }

  /**
   * The async collector: a chain that returns every value of {@code source} since its last call.
   *
   * @param name the collector chain's name
   * @param source the source it reads
   */
  record AsyncCollector(String name, String source) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name the collector chain's name
     * @param source the source it reads
     */
    public AsyncCollector {
      Objects.requireNonNull(name, "name");
      Objects.requireNonNull(source, "source");
    }

    @Override
    public List<Part> parts() {
      return List.of(new Part("source", source, Flow.READS));
    }

    @Override
    public boolean isService() {
      return true;
    }

    @Override
    public boolean isChain() {
      return true;
    }
  }

  /**
   * The repeater: runs {@code inner} in a loop until its deciding block says stop.
   *
   * @param name the repeater chain's name
   * @param inner the chain run each round
   * @param collector the async collector of the source it watches between rounds, or {@code
   *     null}
   */
  record Repeater(String name, String inner, String collector) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name the repeater chain's name
     * @param inner the chain run each round
     * @param collector the async collector of the source it watches between rounds, or {@code null}
     */
    public Repeater {
      Objects.requireNonNull(name, "name");
      Objects.requireNonNull(inner, "inner");
    }

    @Override
    public List<Part> parts() {
      return collector == null
          ? List.of(new Part("inner", inner, Flow.RUNS))
          : List.of(
              new Part("inner", inner, Flow.RUNS), new Part("collects", collector, Flow.RUNS));
    }

    @Override
    public boolean isService() {
      return true;
    }

    @Override
    public boolean isChain() {
      return true;
    }
  }

  /**
   * A source fed by an event block ({@code core.source(events)}).
   *
   * @param name the source's name
   */
  record EventSource(String name) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name the source's name
     */
    public EventSource {
      Objects.requireNonNull(name, "name");
    }

    @Override
    public List<Part> parts() {
      return List.of();
    }

    @Override
    public boolean isService() {
      return false;
    }

    @Override
    public boolean isChain() {
      return false;
    }
  }

  /**
   * A source of another core read here.
   *
   * @param name its name in this topology
   * @param core the core it belongs to
   * @param source its name in that core
   */
  record ForeignSource(String name, String core, String source) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name its name in this topology
     * @param core the core it belongs to
     * @param source its name in that core
     */
    public ForeignSource {
      Objects.requireNonNull(name, "name");
      Objects.requireNonNull(core, "core");
      Objects.requireNonNull(source, "source");
    }

    @Override
    public List<Part> parts() {
      return List.of();
    }

    @Override
    public boolean isService() {
      return false;
    }

    @Override
    public boolean isChain() {
      return false;
    }
  }

  /**
   * A chain linked to a source: the chain runs on every value of {@code source}; this node is the
   * source of its outputs.
   *
   * @param name the output source's name ({@code source>chain})
   * @param source the input source
   * @param chain the chain that runs on it
   */
  record SourceLink(String name, String source, String chain) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name the output source's name ({@code source>chain})
     * @param source the input source
     * @param chain the chain that runs on it
     */
    public SourceLink {
      Objects.requireNonNull(name, "name");
      Objects.requireNonNull(source, "source");
      Objects.requireNonNull(chain, "chain");
    }

    @Override
    public List<Part> parts() {
      return List.of(new Part("source", source, Flow.READS), new Part("chain", chain, Flow.READS));
    }

    @Override
    public boolean isService() {
      return false;
    }

    @Override
    public boolean isChain() {
      return false;
    }
  }

  /**
   * {@code source.filter(predicate)}: a service and the source of the values that pass.
   *
   * @param name the filtered source's name
   * @param source the input source
   */
  record Filter(String name, String source) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name the filtered source's name
     * @param source the input source
     */
    public Filter {
      Objects.requireNonNull(name, "name");
      Objects.requireNonNull(source, "source");
    }

    @Override
    public List<Part> parts() {
      return List.of(new Part("source", source, Flow.READS));
    }

    @Override
    public boolean isService() {
      return true;
    }

    @Override
    public boolean isChain() {
      return false;
    }
  }

  /**
   * {@code source.flatMap(block)}: a service and the source of the values it makes.
   *
   * @param name the flattened source's name
   * @param source the input source
   */
  record FlatMap(String name, String source) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name the flattened source's name
     * @param source the input source
     */
    public FlatMap {
      Objects.requireNonNull(name, "name");
      Objects.requireNonNull(source, "source");
    }

    @Override
    public List<Part> parts() {
      return List.of(new Part("source", source, Flow.READS));
    }

    @Override
    public boolean isService() {
      return true;
    }

    @Override
    public boolean isChain() {
      return false;
    }
  }

  /**
   * {@code source.listen(consumer)}: a service that calls a consumer with every value.
   *
   * @param name the listener's name
   * @param source the source it listens to
   */
  record Listener(String name, String source) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name the listener's name
     * @param source the source it listens to
     */
    public Listener {
      Objects.requireNonNull(name, "name");
      Objects.requireNonNull(source, "source");
    }

    @Override
    public List<Part> parts() {
      return List.of(new Part("source", source, Flow.READS));
    }

    @Override
    public boolean isService() {
      return true;
    }

    @Override
    public boolean isChain() {
      return false;
    }
  }

  /**
   * A reader the program opened on a source ({@code source.reader()}); readers the core opens for
   * its own services are not listed. Its name, {@code "<source> reader <n>"}, contains spaces, so it
   * never equals the name of a chain or a source.
   *
   * @param source the source it reads
   * @param number 1 for the first reader the program opened on that source, 2 for the next, ...
   */
  record ReaderNode(String source, int number) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param source the source it reads
     * @param number 1 for the first reader the program opened on that source, 2 for the next, ...
     */
    public ReaderNode {
      Objects.requireNonNull(source, "source");
      if (number < 1) {
        throw new IllegalArgumentException("reader numbers start at 1, was " + number);
      }
    }

    @Override
    public String name() {
      return source + " reader " + number;
    }

    @Override
    public List<Part> parts() {
      return List.of(new Part("source", source, Flow.READS));
    }

    @Override
    public boolean isService() {
      return false;
    }

    @Override
    public boolean isChain() {
      return false;
    }
  }

  /**
   * A generic service ({@code core.service(name, service)}): a service of its own, fed by no
   * source, that runs an initialize step and then its work step over and over (see {@link
   * dev.prime.GenericService}).
   *
   * @param name the service's name
   */
  record GenericServiceNode(String name) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name the service's name
     */
    public GenericServiceNode {
      Objects.requireNonNull(name, "name");
    }

    @Override
    public List<Part> parts() {
      return List.of();
    }

    @Override
    public boolean isService() {
      return true;
    }

    @Override
    public boolean isChain() {
      return false;
    }
  }

  /**
   * A combinator of sources ({@code core.combineLatest}, {@code core.zip}, {@code core.merge},
   * {@code source.withLatestFrom}, {@code source.sample}): a service and the source of what it
   * emits.
   *
   * @param name the output source's name ({@code kind(a|b|...)})
   * @param kind {@code combineLatest}, {@code zip}, {@code merge}, {@code withLatestFrom} or
   *     {@code sample}
   * @param sources its inputs, in order
   */
  record Combinator(String name, String kind, List<String> sources) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name the output source's name
     * @param kind which combinator
     * @param sources its inputs, in order
     */
    public Combinator {
      Objects.requireNonNull(name, "name");
      Objects.requireNonNull(kind, "kind");
      sources = List.copyOf(sources);
    }

    @Override
    public List<Part> parts() {
      return sources.stream()
          .map(source -> new Part("source", source, Flow.READS))
          .toList();
    }

    @Override
    public boolean isService() {
      return true;
    }

    @Override
    public boolean isChain() {
      return false;
    }
  }

  /**
   * A timer ({@code core.timer(name, period)}): a service and the source of its ticks.
   *
   * @param name the timer's name
   * @param period the time between two ticks
   */
  record Timer(String name, java.time.Duration period) implements TopologyNode {
    /**
     * Checks the components.
     *
     * @param name the timer's name
     * @param period the time between two ticks
     */
    public Timer {
      Objects.requireNonNull(name, "name");
      Objects.requireNonNull(period, "period");
    }

    @Override
    public List<Part> parts() {
      return List.of();
    }

    @Override
    public boolean isService() {
      return true;
    }

    @Override
    public boolean isChain() {
      return false;
    }
  }
}

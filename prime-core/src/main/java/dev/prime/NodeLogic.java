package dev.prime;

import java.util.Objects;
import java.util.function.Consumer;
import java.util.function.Predicate;

/**
 * The logic of one node of the topology model: what a media needs, besides the node itself
 * ({@link dev.prime.topology.TopologyNode}: name, kind, parts), to compile it. The public model
 * stays free of logic (it is data to draw and compare); the core keeps each node's logic next to
 * it while the node is declared and compiled, and a {@link ChainCompiler}
 * receives it with the node.
 *
 * <p>Which node kind carries which logic:
 *
 * <table>
 *   <caption>Node kinds and their logic</caption>
 *   <tr><th>node</th><th>logic</th></tr>
 *   <tr><td>{@code BlockChain}</td><td>{@link Run}: the user's block</td></tr>
 *   <tr><td>{@code ForeignChain}</td><td>{@link OtherChain}: the other core's chain</td></tr>
 *   <tr><td>{@code Link}, {@code ForEach}, {@code Union}, {@code SourceLink}</td>
 *       <td>{@link None}: their parts are all they are made of</td></tr>
 *   <tr><td>{@code IfElse}, {@code Filter}</td><td>{@link Condition}</td></tr>
 *   <tr><td>{@code Fork}, {@code EventSource}</td><td>{@link Events}</td></tr>
 *   <tr><td>{@code Guard}</td><td>{@link Guarded}: the predicate and the substitute</td></tr>
 *   <tr><td>{@code IsolatedUser}</td><td>{@link Shared}: the block all users share</td></tr>
 *   <tr><td>{@code SyncCollector}, {@code AsyncCollector}</td><td>{@link Collect}: the source
 *       read</td></tr>
 *   <tr><td>{@code Repeater}</td><td>{@link Repeat}: the repeater block</td></tr>
 *   <tr><td>{@code FlatMap}</td><td>{@link Expand}</td></tr>
 *   <tr><td>{@code Listener}</td><td>{@link Listen}</td></tr>
 *   <tr><td>{@code ForeignSource}</td><td>{@link OtherSource}: the other core's source</td></tr>
 *   <tr><td>{@code ReaderNode}</td><td>{@link None}</td></tr>
 *   <tr><td>{@code GenericServiceNode}</td><td>{@link Work}: the generic service</td></tr>
 *   <tr><td>{@code Combinator}, {@code Timer}</td><td>{@link None}: the node says all (its kind,
 *       inputs and period); the core runs them on its own threads, no media compiles them</td></tr>
 * </table>
 */
public sealed interface NodeLogic {

  /** A node made of its parts only. */
  record None() implements NodeLogic {
    /** The one value. */
    public static final None NONE = new None();
  }

  /**
   * A chain's block.
   *
   * @param block the user's block
   */
  record Run(Block<?, ?> block) implements NodeLogic {
    /**
     * @param block the user's block
     */
    public Run {
      Objects.requireNonNull(block, "block");
    }
  }

  /**
   * A chain of another core used here; a media takes it through its {@link Chain#toBlock()}.
   *
   * @param chain the chain
   */
  record OtherChain(Chain<?, ?> chain) implements NodeLogic {
    /**
     * @param chain the chain
     */
    public OtherChain {
      Objects.requireNonNull(chain, "chain");
    }
  }

  /**
   * A source of another core read here.
   *
   * @param source the source
   */
  record OtherSource(Source<?> source) implements NodeLogic {
    /**
     * @param source the source
     */
    public OtherSource {
      Objects.requireNonNull(source, "source");
    }
  }

  /**
   * The condition of an if/else (true: {@code then}) or of a filter (true: pass).
   *
   * @param condition the predicate
   */
  record Condition(Predicate<?> condition) implements NodeLogic {
    /**
     * @param condition the predicate
     */
    public Condition {
      Objects.requireNonNull(condition, "condition");
    }
  }

  /**
   * The event block of a source (what it publishes) or of a fork (what it publishes to).
   *
   * @param events the event block
   */
  record Events(EventBlock<?> events) implements NodeLogic {
    /**
     * @param events the event block
     */
    public Events {
      Objects.requireNonNull(events, "events");
    }
  }

  /**
   * A guard's logic.
   *
   * @param pass decides which inputs run the guarded chain
   * @param substitute the output for the others
   */
  record Guarded(Predicate<?> pass, Block<?, ?> substitute) implements NodeLogic {
    /**
     * @param pass decides which inputs run the guarded chain
     * @param substitute the output for the others
     */
    public Guarded {
      Objects.requireNonNull(pass, "pass");
      Objects.requireNonNull(substitute, "substitute");
    }
  }

  /**
   * The block every user of an isolated chain calls (it runs the shared chain one call at a time).
   *
   * @param block the shared block
   */
  record Shared(Block<?, ?> block) implements NodeLogic {
    /**
     * @param block the shared block
     */
    public Shared {
      Objects.requireNonNull(block, "block");
    }
  }

  /**
   * The source a collector reads.
   *
   * @param source the source (of this core or another)
   */
  record Collect(Source<?> source) implements NodeLogic {
    /**
     * @param source the source
     */
    public Collect {
      Objects.requireNonNull(source, "source");
    }
  }

  /**
   * A repeater's decision block.
   *
   * @param repeater decides after each round
   */
  record Repeat(RepeaterBlock<?, ?, ?, ?> repeater) implements NodeLogic {
    /**
     * @param repeater decides after each round
     */
    public Repeat {
      Objects.requireNonNull(repeater, "repeater");
    }
  }

  /**
   * A flat-map's block.
   *
   * @param block makes the values published for each input
   */
  record Expand(Block<?, ? extends Iterable<?>> block) implements NodeLogic {
    /**
     * @param block makes the values published for each input
     */
    public Expand {
      Objects.requireNonNull(block, "block");
    }
  }

  /**
   * A listener.
   *
   * @param listener called with every value
   */
  record Listen(Consumer<?> listener) implements NodeLogic {
    /**
     * @param listener called with every value
     */
    public Listen {
      Objects.requireNonNull(listener, "listener");
    }
  }

  /**
   * A generic service: what it initializes, works and shuts down (see {@link
   * GenericServiceLoop}).
   *
   * @param service the user's service
   */
  record Work(GenericService service) implements NodeLogic {
    /**
     * @param service the user's service
     */
    public Work {
      Objects.requireNonNull(service, "service");
    }
  }
}

package dev.prime.radiant;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.CoreConfig;
import dev.prime.EventBlock;
import dev.prime.PrimeCore;
import dev.prime.Tuple2;
import dev.prime.Tuple3;
import dev.prime.Tuple4;
import dev.prime.Tuple5;
import dev.prime.radiant.internal.Node;
import java.util.List;
import java.util.Objects;
import java.util.function.Predicate;

/**
 * The Radiant media: a chain is a tree of nodes, and {@link Chain#toBlock()} compiles the whole
 * linked tree into one generated class whose {@code process} method calls every block through a
 * call site of its own. Links, if/else, for-each, unions, forks and guards become bytecode in that
 * method, so a linked chain runs at the speed of hand-written calls, and its blocks stay inlinable
 * however many different chains the program has.
 *
 * <p>A chain of more than 200 call sites (blocks, conditions, template code) is too long for one
 * method that the JIT still compiles; it is split into several generated classes, each holding a
 * segment of the chain, run one after the other by a small driver class, so chains of any length
 * (100,000 links and more) compile and run on a default thread stack.
 *
 * <pre>{@code
 * try (PrimeCore core = new RadiantCore()) {
 *   Block<Integer, Integer> plusThree =
 *       core.chain((Integer x) -> x + 1).then((Integer x) -> x + 2).toBlock(); // one class
 *   plusThree.process(1); // 4
 * }
 * }</pre>
 *
 * <p>Isolate, the collectors and the repeater use the generic templates of {@link PrimeCore}: their
 * blocks are called from the fused class as leaves. Sources, readers and service threads are
 * {@link PrimeCore}'s in-memory defaults; a chain linked to a source is compiled once and runs as
 * one service. A block that throws reaches the caller as a {@link dev.prime.ChainFailedException}
 * naming the innermost chain that failed, with the user's block directly under the fused class in
 * the stack trace. A fused class is unloaded once its block is no longer referenced.
 *
 * <p>Thread-safe. Compiling costs a class definition per {@code toBlock()}: do it once, when the
 * topology is built, and call the block many times.
 */
public final class RadiantCore extends PrimeCore {

  /** A core with the default settings. */
  public RadiantCore() {
    this(CoreConfig.defaults());
  }

  /**
   * A core with the given settings.
   *
   * @param config the settings
   */
  public RadiantCore(CoreConfig config) {
    super("radiant", config);
  }

  @Override
  protected <I, O> Chain<I, O> newChain(String name, Block<I, O> block) {
    return new RadiantChain<>(this, name, new Node.Leaf(name, block));
  }

  /**
   * Links two chains into one tree; chains of another core become opaque nodes (see {@link
   * PrimeCore#part}).
   */
  @Override
  public <I, M, O> Chain<I, O> link(Chain<I, M> first, Chain<? super M, O> second) {
    requireChains(first, second);
    String name = topologyRecorder().link(first, second);
    Node a = part(first, Node.class, Node.Opaque::new);
    Node b = part(second, Node.class, Node.Opaque::new);
    return new RadiantChain<>(this, name, new Node.Link(a, b));
  }

  @Override
  public <I, O> Chain<I, O> ifThenElse(
      Predicate<? super I> condition, Chain<I, O> then, Chain<I, O> otherwise) {
    Objects.requireNonNull(condition, "condition must not be null");
    requireChains(then, otherwise);
    String name = topologyRecorder().ifElse(then, otherwise);
    Node a = part(then, Node.class, Node.Opaque::new);
    Node b = part(otherwise, Node.class, Node.Opaque::new);
    return new RadiantChain<>(this, name, new Node.IfElse(name, condition, a, b));
  }

  @Override
  public <I, O> Chain<List<I>, List<O>> forEach(Chain<I, O> body) {
    requireChains(body);
    String name = topologyRecorder().forEach(body);
    Node node = part(body, Node.class, Node.Opaque::new);
    return new RadiantChain<>(this, name, new Node.ForEach(name, node));
  }

  @Override
  public <I, A, B> Chain<I, Tuple2<A, B>> union(Chain<I, A> a, Chain<I, B> b) {
    return fusedUnion(a, b);
  }

  @Override
  public <I, A, B, C> Chain<I, Tuple3<A, B, C>> union(
      Chain<I, A> a, Chain<I, B> b, Chain<I, C> c) {
    return fusedUnion(a, b, c);
  }

  @Override
  public <I, A, B, C, D> Chain<I, Tuple4<A, B, C, D>> union(
      Chain<I, A> a, Chain<I, B> b, Chain<I, C> c, Chain<I, D> d) {
    return fusedUnion(a, b, c, d);
  }

  @Override
  public <I, A, B, C, D, E> Chain<I, Tuple5<A, B, C, D, E>> union(
      Chain<I, A> a, Chain<I, B> b, Chain<I, C> c, Chain<I, D> d, Chain<I, E> e) {
    return fusedUnion(a, b, c, d, e);
  }

  @Override
  public <I, O> Chain<I, O> fork(Chain<I, O> chain, EventBlock<? super O> events) {
    Objects.requireNonNull(events, "events must not be null");
    requireChains(chain);
    String name = topologyRecorder().fork(chain);
    Node node = part(chain, Node.class, Node.Opaque::new);
    return new RadiantChain<>(this, name, new Node.Fork(name, node, events));
  }

  @Override
  public <I, O> Chain<I, O> guard(
      Predicate<? super I> pass, Chain<I, O> chain, Block<? super I, ? extends O> substitute) {
    Objects.requireNonNull(pass, "pass predicate must not be null");
    Objects.requireNonNull(substitute, "substitute must not be null");
    requireChains(chain);
    String name = topologyRecorder().guard(chain);
    Node node = part(chain, Node.class, Node.Opaque::new);
    return new RadiantChain<>(this, name, new Node.Guard(name, pass, node, substitute));
  }

  /** The tuple type is chosen by the number of parts, in the generated code. */
  private <I, T> Chain<I, T> fusedUnion(Chain<?, ?>... parts) {
    requireChains(parts);
    String name = topologyRecorder().union(parts);
    Node[] nodes = new Node[parts.length];
    for (int i = 0; i < parts.length; i++) {
      nodes[i] = part(parts[i], Node.class, Node.Opaque::new);
    }
    return new RadiantChain<>(this, name, new Node.Union(name, List.of(nodes)));
  }
}

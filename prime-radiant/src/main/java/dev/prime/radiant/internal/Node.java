package dev.prime.radiant.internal;

import dev.prime.Block;
import dev.prime.EventBlock;
import java.util.List;
import java.util.Objects;
import java.util.function.Predicate;

/**
 * A Radiant chain as data: the tree that {@link FusedCompiler} turns into one class. Nodes are
 * immutable; a chain's node is handed to the chain that consumes it, so a node belongs to exactly
 * one tree.
 *
 * <p>Every node that runs code of its own (a condition, a substitute, a publication) carries the
 * name of its chain, so a failure there is reported as that chain's, as in the other media.
 */
public sealed interface Node {

  /** The nodes this node runs. */
  List<Node> children();

  /**
   * This node with other children (same number, same order).
   *
   * @param children replacements for {@link #children()}
   * @return the new node
   */
  Node withChildren(List<Node> children);

  /** Call sites this node emits itself, children excluded: a measure of method size. */
  int ownSites();

  /** Call sites of the whole subtree. */
  default int sites() {
    int sum = ownSites();
    for (Node child : children()) {
      sum += child.sites();
    }
    return sum;
  }

  /**
   * A block the media does not look inside, called through its own call site; what it throws
   * reaches the caller as a {@link dev.prime.ChainFailedException} naming {@code chain}. The
   * block is a user's block or a template the media does not fuse (isolate, collectors,
   * repeater).
   *
   * @param chain the chain's name
   * @param block the block
   */
  record Leaf(String chain, Block<?, ?> block) implements Node {
    public Leaf {
      Objects.requireNonNull(chain, "chain");
      Objects.requireNonNull(block, "block");
    }

    @Override
    public List<Node> children() {
      return List.of();
    }

    @Override
    public Node withChildren(List<Node> children) {
      return this;
    }

    @Override
    public int ownSites() {
      return 1;
    }
  }

  /**
   * A block that names its own failures (a chain of another core or media, or a part of this
   * chain compiled separately): called through its own call site, exceptions pass unchanged.
   *
   * @param block the block
   */
  record Opaque(Block<?, ?> block) implements Node {
    public Opaque {
      Objects.requireNonNull(block, "block");
    }

    @Override
    public List<Node> children() {
      return List.of();
    }

    @Override
    public Node withChildren(List<Node> children) {
      return this;
    }

    @Override
    public int ownSites() {
      return 1;
    }
  }

  /**
   * {@code second(first(x))}.
   *
   * @param first runs first
   * @param second runs on its output
   */
  record Link(Node first, Node second) implements Node {
    @Override
    public List<Node> children() {
      return List.of(first, second);
    }

    @Override
    public Node withChildren(List<Node> children) {
      return new Link(children.get(0), children.get(1));
    }

    @Override
    public int ownSites() {
      return 0;
    }
  }

  /**
   * {@code condition(x) ? then(x) : otherwise(x)}.
   *
   * @param chain the name that a failing condition is reported under
   * @param condition chooses the branch
   * @param then runs when it holds
   * @param otherwise runs when it does not
   */
  record IfElse(String chain, Predicate<?> condition, Node then, Node otherwise) implements Node {
    @Override
    public List<Node> children() {
      return List.of(then, otherwise);
    }

    @Override
    public Node withChildren(List<Node> children) {
      return new IfElse(chain, condition, children.get(0), children.get(1));
    }

    @Override
    public int ownSites() {
      return 1;
    }
  }

  /**
   * Runs {@code body} on every element of the input list and returns the list of outputs.
   *
   * @param chain the name that a failure of the loop itself (null input, not a list) is
   *     reported under
   * @param body runs once per element
   */
  record ForEach(String chain, Node body) implements Node {
    @Override
    public List<Node> children() {
      return List.of(body);
    }

    @Override
    public Node withChildren(List<Node> children) {
      return new ForEach(chain, children.get(0));
    }

    @Override
    public int ownSites() {
      return 6;
    }
  }

  /**
   * Gives the input to every part, in order, and returns a {@code TupleN} of the outputs.
   *
   * @param chain the union chain's name
   * @param parts 2 to 5 parts
   */
  record Union(String chain, List<Node> parts) implements Node {
    public Union {
      if (parts.size() < 2 || parts.size() > 5) {
        throw new IllegalArgumentException("a union has 2 to 5 parts, not " + parts.size());
      }
      parts = List.copyOf(parts);
    }

    @Override
    public List<Node> children() {
      return parts;
    }

    @Override
    public Node withChildren(List<Node> children) {
      return new Union(chain, children);
    }

    @Override
    public int ownSites() {
      return 1;
    }
  }

  /**
   * Runs {@code body} and publishes each non-null output to {@code events}.
   *
   * @param chain the name that a failing publication is reported under
   * @param body computes the output
   * @param events receives it
   */
  record Fork(String chain, Node body, EventBlock<?> events) implements Node {
    @Override
    public List<Node> children() {
      return List.of(body);
    }

    @Override
    public Node withChildren(List<Node> children) {
      return new Fork(chain, children.get(0), events);
    }

    @Override
    public int ownSites() {
      return 1;
    }
  }

  /**
   * {@code pass(x) ? body(x) : substitute(x)}.
   *
   * @param chain the name that a failing predicate or substitute is reported under
   * @param pass decides
   * @param body the guarded chain
   * @param substitute the output for inputs that do not pass
   */
  record Guard(String chain, Predicate<?> pass, Node body, Block<?, ?> substitute)
      implements Node {
    @Override
    public List<Node> children() {
      return List.of(body);
    }

    @Override
    public Node withChildren(List<Node> children) {
      return new Guard(chain, pass, children.get(0), substitute);
    }

    @Override
    public int ownSites() {
      return 2;
    }
  }
}

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
 *
 * <p>Linking builds a binary {@link Link} per {@code then}, so a chain of n links is a tree n deep.
 * Nothing walks a tree recursively: the compiler flattens spines of links into {@link Sequence}s
 * and visits nodes with explicit stacks, and {@code toString} of a node shows its kind and its
 * children's kinds only. ({@code equals} and {@code hashCode} are the records' own and do
 * descend: the compiler keys its maps by identity, never by node.)
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

  /**
   * Call sites this node emits itself, children excluded: a measure of method size. (A subtree's
   * total is summed by {@link TreeSplitter} while it walks the tree, never recursively: trees are
   * as deep as chains are long.)
   */
  int ownSites();

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
    public Link {
      Objects.requireNonNull(first, "first");
      Objects.requireNonNull(second, "second");
    }

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

    @Override
    public String toString() {
      return shallow(this);
    }
  }

  /**
   * {@code steps[n-1](...steps[1](steps[0](x)))}: a spine of {@link Link}s flattened, which is
   * how the compiler sees links (the cores build binary links, one per {@code then}).
   *
   * @param steps two or more nodes (the compiler flattens links and sequences among them too)
   */
  record Sequence(List<Node> steps) implements Node {
    public Sequence {
      if (steps.size() < 2) {
        throw new IllegalArgumentException("a sequence has 2 or more steps, not " + steps.size());
      }
      steps = List.copyOf(steps);
    }

    @Override
    public List<Node> children() {
      return steps;
    }

    @Override
    public Node withChildren(List<Node> children) {
      return new Sequence(children);
    }

    @Override
    public int ownSites() {
      return 0;
    }

    @Override
    public String toString() {
      return shallow(this);
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

    @Override
    public String toString() {
      return shallow(this);
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

    @Override
    public String toString() {
      return shallow(this);
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

    @Override
    public String toString() {
      return shallow(this);
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

    @Override
    public String toString() {
      return shallow(this);
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

    @Override
    public String toString() {
      return shallow(this);
    }
  }

  /** A node's kind and its children's kinds, without descending: trees may be very deep. */
  private static String shallow(Node node) {
    StringBuilder b = new StringBuilder(node.getClass().getSimpleName()).append('[');
    List<Node> children = node.children();
    for (int i = 0; i < children.size() && i < 5; i++) {
      b.append(i == 0 ? "" : ", ").append(children.get(i).getClass().getSimpleName());
    }
    return b.append(children.size() > 5 ? ", ...]" : "]").toString();
  }
}

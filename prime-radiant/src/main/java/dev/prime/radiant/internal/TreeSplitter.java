package dev.prime.radiant.internal;

import dev.prime.Block;
import java.util.ArrayDeque;
import java.util.ArrayList;
import java.util.Deque;
import java.util.List;
import java.util.function.Function;

/**
 * Splits a chain's tree into pieces small enough for one generated method each, and flattens
 * spines of links into {@link Node.Sequence}s on the way.
 *
 * <p>Design note. A method holds at most {@link #maxSites} call sites (see
 * {@link FusedCompiler#MAX_SITES}). The tree is walked once, bottom-up, with an explicit stack
 * (a chain of n links is a tree n deep, so recursion would overflow the thread's stack). Each node
 * is finished once its children are: it keeps the sites its children left inline plus its own.
 * <ul>
 *   <li>A spine of links (any mix of left- and right-nested {@code then}s) becomes one sequence of
 *       steps. If its steps have more sites than a method may hold, consecutive steps are grouped
 *       into segments of at most {@code maxSites} sites, each compiled into a class of its own
 *       and left in the sequence as one opaque call; if there are still too many segments, they
 *       are grouped again. A chain of n blocks thus runs as a shallow tree of straight-line
 *       methods: a driver calls segments one after the other, and the depth of calls is
 *       log<sub>maxSites</sub>(n), never n.
 *   <li>Any other node (if/else, guard, for-each, union, fork) whose children leave too many
 *       sites has its heaviest children compiled into classes of their own, one by one, until it
 *       fits. Nested templates run one nested call per {@code maxSites} sites of nesting.
 * </ul>
 * A tree that fits from the start (every chain up to {@code maxSites} sites, templates included)
 * is not split at all: one class, one straight-line method. Not thread-safe; one per compilation.
 */
final class TreeSplitter {
  private final int maxSites;
  private final Function<Node, Block<?, ?>> compilePiece;

  /**
   * @param maxSites most call sites one method may hold
   * @param compilePiece compiles a piece that fits into a class of its own and returns its block
   */
  TreeSplitter(int maxSites, Function<Node, Block<?, ?>> compilePiece) {
    this.maxSites = maxSites;
    this.compilePiece = compilePiece;
  }

  /** A node as it will be emitted, and the call sites it puts into the method that emits it. */
  private record Fitted(Node node, int sites) {}

  /** A node being fitted: its children (for a spine of links, its steps) and those done. */
  private static final class Frame {
    final Node node;
    final List<Node> children;
    final List<Fitted> done;

    Frame(Node node) {
      this.node = node;
      this.children = isSpine(node) ? steps(node) : node.children();
      this.done = new ArrayList<>(children.size());
    }
  }

  /**
   * Fits a tree.
   *
   * @param root the chain's tree
   * @return an equivalent tree with no links, whose every method-sized part fits
   */
  Node split(Node root) {
    Deque<Frame> stack = new ArrayDeque<>();
    stack.push(new Frame(root));
    while (true) {
      Frame top = stack.peek();
      if (top.done.size() < top.children.size()) {
        stack.push(new Frame(top.children.get(top.done.size())));
        continue;
      }
      stack.pop();
      Fitted fitted = finish(top);
      if (stack.isEmpty()) {
        return fitted.node();
      }
      stack.peek().done.add(fitted);
    }
  }

  private Fitted finish(Frame frame) {
    if (isSpine(frame.node)) {
      return sequence(frame.done);
    }
    if (frame.done.isEmpty()) {
      return new Fitted(frame.node, frame.node.ownSites());
    }
    List<Fitted> children = new ArrayList<>(frame.done);
    int sites = frame.node.ownSites() + sum(children);
    while (sites > maxSites) {
      int heaviest = 0;
      for (int i = 1; i < children.size(); i++) {
        if (children.get(i).sites() > children.get(heaviest).sites()) {
          heaviest = i;
        }
      }
      Fitted cut = children.get(heaviest);
      if (cut.sites() <= 1) {
        break; // cannot happen while maxSites exceeds a node's own sites plus its child count
      }
      children.set(heaviest, piece(cut.node()));
      sites -= cut.sites() - 1;
    }
    List<Node> nodes = new ArrayList<>(children.size());
    for (Fitted child : children) {
      nodes.add(child.node());
    }
    return new Fitted(frame.node.withChildren(nodes), sites);
  }

  /** Steps run one after another; grouped into segments of their own while they do not fit. */
  private Fitted sequence(List<Fitted> steps) {
    int sites = sum(steps);
    while (sites > maxSites) {
      List<Fitted> segments = new ArrayList<>();
      List<Fitted> current = new ArrayList<>();
      int currentSites = 0;
      for (Fitted step : steps) {
        if (!current.isEmpty() && currentSites + step.sites() > maxSites) {
          segments.add(segment(current));
          current = new ArrayList<>();
          currentSites = 0;
        }
        current.add(step);
        currentSites += step.sites();
      }
      segments.add(segment(current));
      steps = segments;
      sites = sum(steps);
    }
    return new Fitted(sequenceOf(steps), sites);
  }

  private Fitted segment(List<Fitted> steps) {
    if (steps.size() == 1 && steps.get(0).sites() <= 1) {
      return steps.get(0); // one call already: a class of its own would only add one
    }
    return piece(sequenceOf(steps));
  }

  private Fitted piece(Node node) {
    return new Fitted(new Node.Opaque(compilePiece.apply(node)), 1);
  }

  private static Node sequenceOf(List<Fitted> steps) {
    if (steps.size() == 1) {
      return steps.get(0).node();
    }
    List<Node> nodes = new ArrayList<>(steps.size());
    for (Fitted step : steps) {
      nodes.add(step.node());
    }
    return new Node.Sequence(nodes);
  }

  private static int sum(List<Fitted> fitted) {
    int sum = 0;
    for (Fitted f : fitted) {
      sum += f.sites();
    }
    return sum;
  }

  private static boolean isSpine(Node node) {
    return node instanceof Node.Link || node instanceof Node.Sequence;
  }

  /** The nodes a spine of links and sequences runs, in order; iterative, any nesting. */
  private static List<Node> steps(Node spine) {
    List<Node> steps = new ArrayList<>();
    Deque<Node> pending = new ArrayDeque<>();
    pending.push(spine);
    while (!pending.isEmpty()) {
      Node node = pending.pop();
      if (isSpine(node)) {
        List<Node> children = node.children();
        for (int i = children.size() - 1; i >= 0; i--) {
          pending.push(children.get(i));
        }
      } else {
        steps.add(node);
      }
    }
    return steps;
  }
}

package dev.prime.radiant;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.radiant.internal.FusedCompiler;
import dev.prime.radiant.internal.Node;
import dev.prime.spi.AbstractChain;

/**
 * A Radiant chain: a name and the node tree it stands for. Linking and the fused templates build
 * bigger trees from the trees of the chains they consume; {@link #toBlock()} compiles the whole
 * tree into one class.
 */
final class RadiantChain<I, O> extends AbstractChain<I, O> {
  private final Node node;

  RadiantChain(RadiantCore core, String name, Node node) {
    super(core, name);
    this.node = node;
  }

  /**
   * Consumes a chain and returns its tree: a chain of this core gives its tree, any other chain
   * (another core, another media) is called through its {@link Chain#toBlock()} as one opaque
   * node.
   */
  static Node take(RadiantCore core, Chain<?, ?> chain) {
    if (chain instanceof RadiantChain<?, ?> own && own.core() == core) {
      own.consume();
      return own.node;
    }
    return new Node.Opaque(chain.toBlock());
  }

  @Override
  protected Block<I, O> createBlock() {
    return FusedCompiler.compile(name(), node);
  }
}

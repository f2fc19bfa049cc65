package dev.prime.radiant;

import dev.prime.Block;
import dev.prime.radiant.internal.FusedCompiler;
import dev.prime.radiant.internal.Node;
import dev.prime.spi.AbstractChain;

/**
 * A Radiant chain: a name and the node tree it stands for. Linking and the fused templates build
 * bigger trees from the trees of the chains they consume ({@link dev.prime.PrimeCore}'s {@code
 * part}); {@link #toBlock()} compiles the whole tree into one class.
 */
final class RadiantChain<I, O> extends AbstractChain<I, O> {
  private final Node node;

  RadiantChain(RadiantCore core, String name, Node node) {
    super(core, name);
    this.node = node;
  }

  /** The chain's tree: what a link or template of the same core builds a bigger tree from. */
  @Override
  protected Object compiledForm() {
    return node;
  }

  @Override
  protected Block<I, O> createBlock() {
    return FusedCompiler.compile(name(), node);
  }
}

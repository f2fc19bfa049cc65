package dev.prime.liberty;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.spi.AbstractChain;
import dev.prime.spi.FailureNamingBlock;

/**
 * A Liberty chain: a name and the block that runs it.
 *
 * <p>A leaf chain's block is the user's block wrapped once so that a failure names the chain; a
 * composite (linked) chain's block is the composition of its parts' blocks, with no wrapper of its
 * own, so a linked call costs one invocation per block and one per link.
 */
final class LibertyChain<I, O> extends AbstractChain<I, O> {
  private final Block<I, O> block;

  private LibertyChain(LibertyCore core, String name, Block<I, O> block) {
    super(core, name);
    this.block = block;
  }

  static <I, O> LibertyChain<I, O> leaf(LibertyCore core, String name, Block<I, O> block) {
    return new LibertyChain<>(core, name, new FailureNamingBlock<>(name, block));
  }

  static <I, O> LibertyChain<I, O> composite(LibertyCore core, String name, Block<I, O> block) {
    return new LibertyChain<>(core, name, block);
  }

  /** Consumes a chain and returns its block; a chain of this core gives its block directly. */
  static <I, O> Block<I, O> take(LibertyCore core, Chain<I, O> chain) {
    if (chain instanceof LibertyChain<I, O> own && own.core() == core) {
      own.consume();
      return own.block;
    }
    return chain.toBlock();
  }

  @Override
  protected Block<I, O> createBlock() {
    return block;
  }
}

package dev.prime.liberty;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.blocks.LinkBlock;
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

  /**
   * A chain's block as a link of the same core composes it: its own block for a chain of this
   * core, its {@link Chain#toBlock()} for any other ({@link dev.prime.PrimeCore}'s {@code part}).
   *
   * @param block the block
   */
  record Composed(Block<?, ?> block) {}

  /** The composition of two blocks whose types the link has checked. */
  @SuppressWarnings("unchecked")
  static <I, O> Block<I, O> linked(Composed first, Composed second) {
    return new LinkBlock<>((Block<I, Object>) first.block(), (Block<Object, O>) second.block());
  }

  @Override
  protected Object compiledForm() {
    return new Composed(block);
  }

  @Override
  protected Block<I, O> createBlock() {
    return block;
  }
}

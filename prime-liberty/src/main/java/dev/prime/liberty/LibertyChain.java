package dev.prime.liberty;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.spi.AbstractChain;

/**
 * A Liberty chain: a name and the steps that run it.
 *
 * <p>A leaf chain is one step (its block, named after the chain on failure); linking joins the
 * steps of both chains, so a linked chain of any shape is, once it becomes a block, one flat
 * composition of all its steps ({@link FlatComposition}): one invocation per block, no layer per
 * link, no recursion.
 */
final class LibertyChain<I, O> extends AbstractChain<I, O> {
  private final StepSequence steps;

  private LibertyChain(LibertyCore core, String name, StepSequence steps) {
    super(core, name);
    this.steps = steps;
  }

  static <I, O> LibertyChain<I, O> leaf(LibertyCore core, String name, Block<I, O> block) {
    return new LibertyChain<>(core, name, new Step(name, block));
  }

  static <I, O> LibertyChain<I, O> linked(LibertyCore core, String name, StepSequence steps) {
    return new LibertyChain<>(core, name, steps);
  }

  /**
   * Its steps: what a link of the same core joins ({@link dev.prime.PrimeCore}'s {@code part});
   * another core's chain is one unnamed step instead, its {@link Chain#toBlock()} (which names
   * its own failures).
   */
  @Override
  protected Object compiledForm() {
    return steps;
  }

  @Override
  @SuppressWarnings("unchecked")
  protected Block<I, O> createBlock() {
    return (Block<I, O>) (Block<?, ?>) FlatComposition.of(steps.flatten());
  }
}

package dev.prime.liberty;

import dev.prime.Block;
import dev.prime.Chain;
import dev.prime.CoreConfig;
import dev.prime.PrimeCore;

/**
 * The Liberty media: a chain is a function, and linking chains composes their functions, so a
 * linked call costs a few method invocations. Sources are in-memory and broadcast; every chain
 * linked to a source, every filter, flat-map and listener runs on its own service thread.
 *
 * <pre>{@code
 * try (PrimeCore core = new LibertyCore()) {
 *   Block<Integer, Integer> plusThree =
 *       core.chain((Integer x) -> x + 1).then((Integer x) -> x + 2).toBlock();
 *   plusThree.process(1); // 4
 * }
 * }</pre>
 *
 * <p>Thread-safe. Templates use the generic implementations of {@link PrimeCore}.
 */
public final class LibertyCore extends PrimeCore {

  /** A core with the default settings. */
  public LibertyCore() {
    this(CoreConfig.defaults());
  }

  /**
   * A core with the given settings.
   *
   * @param config the settings
   */
  public LibertyCore(CoreConfig config) {
    super("liberty", config);
  }

  @Override
  protected <I, O> Chain<I, O> newChain(String name, Block<I, O> block) {
    return LibertyChain.leaf(this, name, block);
  }

  /**
   * Links two chains by joining their steps: the linked chain's block is one flat composition of
   * every block of both (no layer per link, no recursion, so chains of any length build and run
   * on a default thread stack). Chains of another core are one step each, taken through their
   * {@link Chain#toBlock()}.
   */
  @Override
  public <I, M, O> Chain<I, O> link(Chain<I, M> first, Chain<? super M, O> second) {
    requireChains(first, second);
    String name = topologyRecorder().link(first, second);
    StepSequence a = part(first, StepSequence.class, block -> new Step(null, block));
    StepSequence b = part(second, StepSequence.class, block -> new Step(null, block));
    return LibertyChain.linked(this, name, StepSequence.join(a, b));
  }
}

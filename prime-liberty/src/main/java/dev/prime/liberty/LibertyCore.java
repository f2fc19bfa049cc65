package dev.prime.liberty;

import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.ChainCompiler;

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
 * <p>Thread-safe. Templates other than links use the generic blocks of {@link PrimeCore}.
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

  /**
   * Compiles chains into flat compositions of their steps: a linked chain's block is one flat
   * composition of every block of its parts (no layer per link, no recursion, so chains of any
   * length build and run on a default thread stack).
   */
  @Override
  protected ChainCompiler<?> chainCompiler() {
    return new LibertyCompiler();
  }
}

package dev.prime.radiant;

import dev.prime.Chain;
import dev.prime.CoreConfig;
import dev.prime.PrimeCore;
import dev.prime.ChainCompiler;

/**
 * The Radiant media: a chain is a tree of nodes, and {@link Chain#toBlock()} compiles the whole
 * linked tree into one generated class whose {@code process} method calls every block through a
 * call site of its own. Links, if/else, for-each, unions, forks and guards become bytecode in that
 * method, so a linked chain runs at the speed of hand-written calls, and its blocks stay inlinable
 * however many different chains the program has.
 *
 * <p>A chain of more than 200 call sites (blocks, conditions, template code) is too long for one
 * method that the JIT still compiles; it is split into several generated classes, each holding a
 * segment of the chain, run one after the other by a small driver class, so chains of any length
 * (100,000 links and more) compile and run on a default thread stack.
 *
 * <pre>{@code
 * try (PrimeCore core = new RadiantCore()) {
 *   Block<Integer, Integer> plusThree =
 *       core.chain((Integer x) -> x + 1).then((Integer x) -> x + 2).toBlock(); // one class
 *   plusThree.process(1); // 4
 * }
 * }</pre>
 *
 * <p>Isolate, the collectors and the repeater use the generic templates of {@link PrimeCore}: their
 * blocks are called from the fused class as leaves. Sources, readers and service threads are
 * {@link PrimeCore}'s in-memory defaults; a chain linked to a source is compiled once and runs as
 * one service. A block that throws reaches the caller as a {@link dev.prime.ChainFailedException}
 * naming the innermost chain that failed, with the user's block directly under the fused class in
 * the stack trace. A fused class is unloaded once its block is no longer referenced.
 *
 * <p>Thread-safe. Compiling costs a class definition per {@code toBlock()}: do it once, when the
 * topology is built, and call the block many times.
 */
public final class RadiantCore extends PrimeCore {

  /** A core with the default settings. */
  public RadiantCore() {
    this(CoreConfig.defaults());
  }

  /**
   * A core with the given settings.
   *
   * @param config the settings
   */
  public RadiantCore(CoreConfig config) {
    super("radiant", config);
  }

  /**
   * Compiles chains into node trees (see {@link RadiantCompiler}); a chain of another core becomes
   * an opaque node, called through its {@link Chain#toBlock()}.
   */
  @Override
  protected ChainCompiler<?> chainCompiler() {
    return new RadiantCompiler();
  }
}

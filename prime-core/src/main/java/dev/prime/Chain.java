package dev.prime;

/**
 * A service with one input and one output (topology layer).
 *
 * <p>A chain is created by a {@link PrimeCore} from a {@link Block} and belongs to that core. How
 * the chain runs is the media's choice: a composed function (Liberty), a fused generated class
 * (Radiant) or a service over Redis (Optimus).
 *
 * <h2>Single use</h2>
 * A chain is consumed by {@link #toBlock()} and by every link ({@link #then}, the templates of
 * {@link PrimeCore}): using it a second time throws {@link ChainAlreadyUsedException}. A
 * combined chain replaces its parts; to call one piece of logic from several places, create a
 * chain for each place, or share one with {@link PrimeCore#isolate(Chain)}.
 *
 * <p>Implementations are thread-safe.
 *
 * @param <I> input type
 * @param <O> output type
 */
public interface Chain<I, O> {

  /** {@return the core that created this chain} */
  PrimeCore core();

  /**
   * {@return the chain's name, unique within its core} Optimus derives Redis keys from it, so
   * every process that declares the same topology must give its chains the same names.
   */
  String name();

  /**
   * Converts the chain back to the logic layer, consuming it.
   *
   * <p>The returned block may be called from several threads at once. An exception thrown by a
   * block inside the chain reaches the caller as a {@link ChainFailedException} naming the chain.
   * For media whose chains are services (Optimus) the core must be started first.
   *
   * <p>A block inside the chain that calls the returned block (recursion) recurses on Liberty and
   * Radiant, where the call runs on the caller's thread; on Optimus, whose services take one
   * request at a time, that call, made on the thread that runs the block, fails at once with an
   * {@link IllegalStateException}, unless the block's service is hosted {@code Hosting.UNORDERED}
   * (another host may take it); a call the block hands to another thread waits until the call
   * timeout (see the architecture's <i>Errors</i>). For recursion on every media, let the block
   * call a method of its own.
   *
   * <p>A declaration that fails leaves the chain unused; it can be made again. A {@code
   * toBlock()} that throws (on Optimus, after {@code start()}: its wait for Redis through an
   * outage interrupted, or another process hosting one of the chain's services) stopped and forgot
   * whatever it began, so the same call on this chain works once the cause is gone. Only where the
   * media could not undo it (a service it started did not stop in time) does it throw a {@link
   * ChainAlreadyUsedException} that says so, and the chain stays consumed.
   *
   * @return a block that runs this chain
   * @throws ChainAlreadyUsedException if the chain was already consumed, or its declaration
   *     failed in a way that could not be undone
   */
  Block<I, O> toBlock();

  /**
   * Links this chain's output to {@code next}'s input, consuming both. Like {@link
   * java.util.function.Function#andThen}, {@code next} may take any supertype of this chain's
   * output: a {@code Chain<Integer, Integer>} links to a {@code Chain<Object, String>}.
   *
   * @param next the chain that processes this chain's outputs
   * @param <R> output type of the combined chain
   * @return the combined chain
   * @see PrimeCore#link(Chain, Chain)
   */
  default <R> Chain<I, R> then(Chain<? super O, R> next) {
    return core().link(this, next);
  }

  /**
   * Links this chain to a new chain made of {@code next}, consuming this chain. Like {@link
   * java.util.function.Function#andThen}, {@code next} may take any supertype of this chain's
   * output and return any subtype of {@code R}.
   *
   * @param next the block that processes this chain's outputs
   * @param <R> output type of the combined chain
   * @return the combined chain
   */
  default <R> Chain<I, R> then(Block<? super O, ? extends R> next) {
    return core().linkBlock(this, next);
  }
}

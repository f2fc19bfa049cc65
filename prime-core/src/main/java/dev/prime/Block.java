package dev.prime;

/**
 * A plain function: the unit of logic in Prime.
 *
 * <p>A block knows nothing of chains, sources or media. It is written, and unit-tested, as an
 * ordinary Java object; a {@link PrimeCore} turns it into a {@link Chain} (a service) and decides
 * how chains are connected.
 *
 * <h2>Contract</h2>
 * <ul>
 *   <li><b>Threading.</b> A core calls one block from one thread at a time only when the block
 *       backs exactly one service; a block shared by several chains, or the block returned by
 *       {@link Chain#toBlock()}, may be called concurrently. Blocks that keep state and are
 *       shared should be wrapped with {@link PrimeCore#isolate(Chain)}.
 *   <li><b>Exceptions.</b> A block may throw any unchecked exception. Called synchronously, the
 *       caller receives it wrapped in a {@link ChainFailedException} that names the chain; in an
 *       asynchronous service it goes to the core's {@link ErrorHandler} and the service carries
 *       on with the next value.
 *   <li><b>Nulls.</b> Chains pass {@code null} between blocks if a block returns it; sources never
 *       carry {@code null} (see {@link EventBlock#publish(Object)}).
 * </ul>
 *
 * @param <I> input type
 * @param <O> output type
 */
@FunctionalInterface
public interface Block<I, O> {

  /**
   * Computes the output for one input.
   *
   * @param input the input value
   * @return the output value
   */
  O process(I input);
}

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
 *   <li><b>Exceptions.</b> A block may throw anything; every media treats it the same way:
 *       <table>
 *         <caption>What a block's throwable becomes</caption>
 *         <tr><th>the block throws</th><th>a synchronous caller gets</th>
 *             <th>in an asynchronous service</th></tr>
 *         <tr><td>a {@link RuntimeException}, a checked exception (thrown sneakily), an
 *             {@link Error} such as {@link AssertionError}</td>
 *             <td>a {@link ChainFailedException} naming the chain as the user named it (the
 *             innermost chain of a linked chain), whose cause is the block's own throwable (from a
 *             service in another process: a {@link PrimeException} describing it)</td>
 *             <td>the core's {@link ErrorHandler} gets the chain's name, the input and the
 *             block's own throwable; the service carries on with the next value</td></tr>
 *         <tr><td>a {@link VirtualMachineError} ({@link OutOfMemoryError},
 *             {@link StackOverflowError}, {@link InternalError})</td>
 *             <td>the error itself, unwrapped, when the block runs on the caller's thread (the
 *             in-memory media); a media whose chains are services replies to the caller first
 *             (the very error in the process that ran the block, a {@link ChainFailedException}
 *             describing it in another), then ends that service</td>
 *             <td>it ends that service, logged at ERROR ({@code service '<name>' stops: ...}):
 *             the JVM itself is in trouble; the error handler does not get it</td></tr>
 *         <tr><td>a {@link ClassCastException}, also for a value of the wrong type that reached
 *             it through a raw or unchecked cast</td>
 *             <td>as any exception: a {@link ChainFailedException} naming the chain whose block
 *             took the value</td>
 *             <td>as any exception</td></tr>
 *       </table>
 *       A {@link ChainFailedException} or {@link CoreClosedException} thrown by a block (it called
 *       another chain) passes unchanged to a synchronous caller in the block's process; a caller in
 *       another process gets, as for any failure there, a {@link ChainFailedException}
 *       describing it.
 *   <li><b>Values.</b> Treat inputs and outputs as immutable: a media may hand the same object to
 *       several readers, or a copy (Optimus always copies, through its codec). Do not change a
 *       value after publishing or returning it, nor an input you received.
 *       {@link CoreConfig.Builder#copyValues} makes the in-memory media copy too, so a test
 *       catches a mutation or a type the codec refuses before deployment.
 *   <li><b>Nulls.</b> Chains pass {@code null} between blocks if a block returns it, on every
 *       media and also inside a service; a synchronous caller gets it as the result; a chain
 *       linked to a source publishes nothing for a {@code null} its last block returns. Sources
 *       never carry {@code null} (see {@link EventBlock#publish(Object)}).
 *   <li><b>Interrupts.</b> A block may interrupt its own thread (restore the flag of an {@link
 *       InterruptedException} it caught): a service it runs in clears the flag afterwards and goes
 *       on while the core is open; only {@link PrimeCore#close()} ends a service. In a service,
 *       the blocks run after it on that thread see the flag until the service clears it, before
 *       its next value: on the in-memory media the rest of a linked chain and the later parts of
 *       a template, which a service runs as one function, as hand-written calls would. (On
 *       Optimus each chain and each part of a template is a service of its own, on a thread of
 *       its own; a call of a chain made on a service's thread with the flag set, such as an
 *       {@code ifThenElse} condition's call of its branch, is made as if it were not set, and the
 *       flag is set again after it.) A
 *       block called synchronously on the in-memory media runs on the caller's thread, whose
 *       flag it sets (the next blocks of the call see it too).
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

  /**
   * The same block, seen with narrower types: a block that takes any supertype of {@code I} and
   * returns a subtype of {@code O} is a {@code Block<I, O>}, since a block only takes inputs and
   * only gives outputs. No wrapper: the very object given is returned, so a media that fuses
   * chains still calls the user's block through a call site of its own.
   *
   * <pre>{@code
   * Block<Object, String> describe = String::valueOf;
   * Block<Integer, CharSequence> typed = Block.narrow(describe);
   * }</pre>
   *
   * @param block the block
   * @param <I> the input type wanted
   * @param <O> the output type wanted
   * @return {@code block} itself
   */
  @SuppressWarnings("unchecked") // sound: I is only consumed and O only produced
  static <I, O> Block<I, O> narrow(Block<? super I, ? extends O> block) {
    return (Block<I, O>) block;
  }
}

package dev.prime;

/**
 * A block inside a chain threw. What it threw, exception or error (all but a
 * {@link VirtualMachineError}, which reaches the caller unwrapped), is the
 * {@linkplain #getCause() cause}, the very object (for a service in another process: a
 * {@link PrimeException} describing the remote failure). See {@link Block} for the whole table.
 *
 * <p>When chains are nested, the innermost chain that failed is named; outer chains pass the
 * exception on unchanged.
 */
public class ChainFailedException extends PrimeException {
  private static final long serialVersionUID = 1L;

  /** The name of the chain this exception is about. */
  private final String chainName;

  /**
   * Creates the exception for a chain's failure.
   *
   * @param chainName the chain whose block failed
   * @param cause what the block threw
   */
  public ChainFailedException(String chainName, Throwable cause) {
    super("chain '" + chainName + "' failed: " + cause, cause);
    this.chainName = chainName;
  }

  /** {@return the name of the chain whose block failed} */
  public String chainName() {
    return chainName;
  }
}

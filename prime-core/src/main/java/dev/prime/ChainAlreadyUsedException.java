package dev.prime;

/**
 * A chain was used twice. A chain is consumed by {@link Chain#toBlock()} and by every link or
 * template that takes it; the combined chain replaces it.
 */
public class ChainAlreadyUsedException extends PrimeException {
  private static final long serialVersionUID = 1L;

  /** The name of the chain this exception is about. */
  private final String chainName;

  /**
   * Creates the exception for a chain.
   *
   * @param chainName the chain used twice
   */
  public ChainAlreadyUsedException(String chainName) {
    super(
        "chain '"
            + chainName
            + "' was already used (by toBlock(), a link or a template) and cannot be used again;"
            + " create a new chain from the block for each use, or share one chain with"
            + " PrimeCore.isolate(chain)");
    this.chainName = chainName;
  }

  /** {@return the name of the chain that was used twice} */
  public String chainName() {
    return chainName;
  }
}

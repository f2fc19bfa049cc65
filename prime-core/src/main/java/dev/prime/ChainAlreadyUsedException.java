package dev.prime;

/**
 * A chain was used twice. A chain is consumed by {@link Chain#toBlock()} and by every link or
 * template that takes it; the combined chain replaces it. A declaration that fails leaves its
 * chains unused, except where a media could not undo what the declaration began: it then throws
 * this exception, made with {@link #ChainAlreadyUsedException(String, String, Throwable)}, and
 * the chain stays consumed.
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

  /**
   * Creates the exception for a chain whose declaration failed part-way, where the media could
   * not undo what it had begun: the chain stays consumed.
   *
   * @param chainName the chain that cannot be declared again
   * @param why what the media could not undo, and what to do
   * @param cause the failure of the declaration
   */
  public ChainAlreadyUsedException(String chainName, String why, Throwable cause) {
    super(
        "chain '"
            + chainName
            + "' cannot be declared again: its declaration failed and "
            + why
            + "; declare the block as a new chain (under another name) to use it",
        cause);
    this.chainName = chainName;
  }

  /** {@return the name of the chain that was used twice} */
  public String chainName() {
    return chainName;
  }
}

package dev.prime;

/** A core, or one of its chains, sources or readers, was used after {@link PrimeCore#close()}. */
public class CoreClosedException extends PrimeException {
  private static final long serialVersionUID = 1L;

  /**
   * @param coreName the closed core
   */
  public CoreClosedException(String coreName) {
    super("core '" + coreName + "' is closed; a closed core cannot be used again, create a new one");
  }
}

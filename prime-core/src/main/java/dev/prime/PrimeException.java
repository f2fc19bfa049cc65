package dev.prime;

/** The root of Prime's exceptions: misuse of the API or a failure inside a chain. */
public class PrimeException extends RuntimeException {
  private static final long serialVersionUID = 1L;

  /**
   * @param message what is wrong and how to fix it
   */
  public PrimeException(String message) {
    super(message);
  }

  /**
   * @param message what is wrong and how to fix it
   * @param cause the underlying failure
   */
  public PrimeException(String message, Throwable cause) {
    super(message, cause);
  }
}

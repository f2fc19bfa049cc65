package dev.prime;

/**
 * Receives the failures of asynchronous services: a block that threw while processing a value
 * of a source. After the handler returns, the service goes on with the next value.
 *
 * <p>Called on the service's thread; must be thread-safe if shared. An exception thrown by the
 * handler itself is logged and ignored.
 */
@FunctionalInterface
public interface ErrorHandler {

  /**
   * @param service the name of the failing service
   * @param input the value being processed (never {@code null})
   * @param error what was thrown
   */
  void handle(String service, Object input, Throwable error);
}

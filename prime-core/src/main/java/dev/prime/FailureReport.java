package dev.prime;

import org.slf4j.Logger;
import org.slf4j.LoggerFactory;

/**
 * How a service reports a failure to the core's {@link ErrorHandler}, the same way on every
 * media: a {@link ChainFailedException} (the service called a chain whose block failed) is
 * reported under the failing chain's name with the block's own throwable; anything else under
 * the service's name. A handler that throws is logged at ERROR with the failure suppressed in
 * it, and the service goes on; a {@link VirtualMachineError} from the handler propagates.
 */
public final class FailureReport {

  private static final Logger LOG = LoggerFactory.getLogger(FailureReport.class);

  private FailureReport() {}

  /**
   * Reports one failure.
   *
   * @param handler the core's error handler
   * @param service the name of the service that failed, as the user named it
   * @param input what the service was processing (a value, a tick count, a generic service's
   *     step)
   * @param error what it threw
   */
  public static void report(ErrorHandler handler, String service, Object input, Throwable error) {
    String name = service;
    Throwable own = error;
    if (error instanceof ChainFailedException failed && failed.getCause() != null) {
      name = failed.chainName();
      own = failed.getCause();
    }
    handle(handler, name, input, own);
  }

  /**
   * Gives one failure to the handler as it is, under {@code name}: a handler that throws is
   * logged at ERROR with the failure suppressed in it, and the caller goes on; a {@link
   * VirtualMachineError} from the handler propagates. For failures that are not a service's, such
   * as a {@link PrimeCore#whenRunning} hook's, which the handler gets under the hook's name.
   *
   * @param handler the core's error handler
   * @param name the name the handler gets
   * @param input what failed, as the handler gets it
   * @param error what it threw
   */
  static void handle(ErrorHandler handler, String name, Object input, Throwable error) {
    try {
      handler.handle(name, input, error);
    } catch (VirtualMachineError e) {
      throw e;
    } catch (Throwable handlerFailure) {
      handlerFailure.addSuppressed(error);
      LOG.error("the error handler failed for service '{}'", name, handlerFailure);
    }
  }
}

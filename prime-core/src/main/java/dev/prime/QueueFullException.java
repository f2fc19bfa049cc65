package dev.prime;

/**
 * A publish found the input of a service full and no room came within {@link
 * CoreConfig#publishTimeout()}: nothing of that publish was published. The input of a service is a
 * queue that never drops a value the service has not processed, so a service that cannot keep up
 * holds its publishers up, and after the timeout refuses them. The message names the source, the
 * service and its capacity, and what to do: give the service's input more room (a larger {@link
 * CoreConfig.Builder#sourceRetention}, or the queue limit of a media that has one), make the
 * service faster, or publish fewer values.
 *
 * <p>Thrown the same way by every media; a media may throw a subclass that says more.
 */
public class QueueFullException extends PrimeException {
  private static final long serialVersionUID = 1L;

  /** The service whose input is full. */
  private final String serviceName;

  /** How many unprocessed values its input holds. */
  private final long capacity;

  /**
   * @param serviceName the service whose input is full, as the user named it
   * @param capacity how many unprocessed values its input holds
   * @param message what happened and how to fix it
   */
  public QueueFullException(String serviceName, long capacity, String message) {
    super(message);
    this.serviceName = serviceName;
    this.capacity = capacity;
  }

  /**
   * {@return the service whose input is full, as the user named it and {@link
   * PrimeCore#serviceNames()} lists it: for a chain linked to a source, the chain's name (of chains
   * linked before, the first's), not the name of the source it makes}
   */
  public String serviceName() {
    return serviceName;
  }

  /** {@return how many unprocessed values the service's input holds} */
  public long capacity() {
    return capacity;
  }
}

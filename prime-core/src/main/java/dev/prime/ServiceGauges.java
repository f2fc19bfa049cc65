package dev.prime;

/**
 * What only a media can tell about its services, for {@link dev.prime.Metrics}: how many values
 * wait in a service's input, how many it set aside as dead letters, and how many the readers of
 * an event source missed. A media's {@link
 * ChainCompiler} or {@link SourceCompiler} implements it if its services have such things; the
 * core asks it when a metrics snapshot is taken (not per value), for every metered node by its
 * topology name.
 */
public interface ServiceGauges {
  /**
   * Values in a service's input now that it has not finished: waiting, and taken but not done.
   *
   * @param service a metered node's name
   * @return the count, or {@code -1} if the media has no queue for it (or cannot tell now)
   */
  long queueDepth(String service);

  /**
   * Whether the media has an input queue for a service, whether or not it can read it now; asked
   * when a metrics library registers its meters, so that a queue that cannot be read at that
   * moment still gets its gauge. The default, {@code queueDepth(service) >= 0}, suits a media
   * that can always read its queues; a media that reads them remotely overrides it.
   *
   * @param service a metered node's name
   * @return whether {@link #queueDepth} counts a queue of it
   */
  default boolean hasQueue(String service) {
    return queueDepth(service) >= 0;
  }

  /**
   * Values of a service the media set aside as dead letters.
   *
   * @param service a metered node's name
   * @return the count, 0 if the media keeps none for it, {@code -1} if it cannot tell now
   */
  long deadLetters(String service);

  /**
   * Values the plain readers of an event source missed, as this process counted them (see {@link
   * dev.prime.Reader#missed()}).
   *
   * @param source an event source's name
   * @return the count; 0 by default
   */
  default long missed(String source) {
    return 0;
  }
}

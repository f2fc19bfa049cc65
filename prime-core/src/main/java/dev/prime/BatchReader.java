package dev.prime;

/**
 * A reader that hands its only consumer every value available at once: the input of an
 * in-process service ({@link MemorySource#serviceInput}), which {@link SourceService} drains in
 * batches instead of one {@link Reader#take()} per value. Internal to the core.
 *
 * @param <T> value type
 */
interface BatchReader<T> {
  /**
   * Waits, like {@link Reader#take()}, until a value is available, then hands it and every value
   * after it available by then, in order, to {@code sink}, one by one, until none is left or
   * {@code sink} returns {@code false}. Each value counts as taken before {@code sink} sees it.
   * At low rates a batch is the one value just published: nothing waits for a batch to fill.
   *
   * @param sink what to do with each value; returns whether to go on with the batch
   * @throws InterruptedException if the thread is interrupted while waiting
   * @throws CoreClosedException if the source closed
   * @throws IllegalStateException if this reader is closed
   */
  void takeAvailable(Sink<? super T> sink) throws InterruptedException;

  /**
   * Receives the values of a batch.
   *
   * @param <T> value type
   */
  @FunctionalInterface
  interface Sink<T> {
    /**
     * @param value the next value
     * @return whether to hand over the next value of the batch
     */
    boolean accept(T value);
  }
}

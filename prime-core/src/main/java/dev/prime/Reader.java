package dev.prime;

import java.time.Duration;
import java.util.List;
import java.util.Optional;

/**
 * Reads the values of one {@link Source}, in the order they were published (logic layer).
 *
 * <p>Each reader has its own position: a source is broadcast, so every reader sees every value.
 * A new reader starts at the oldest value the source still retains. If a reader falls more than
 * the source's retention behind, the oldest values it has not read are dropped for it and counted
 * by {@link #missed()}.
 *
 * <p>A reader is meant for one consuming thread; concurrent calls are safe but each value goes to
 * exactly one of the callers. When the core is closed, blocked and later calls throw
 * {@link CoreClosedException}.
 *
 * @param <T> type of the values
 */
public interface Reader<T> {

  /**
   * Returns the next value, waiting until one is published.
   *
   * @return the next value, never {@code null}
   * @throws InterruptedException if the thread is interrupted while waiting
   * @throws CoreClosedException if the core is closed
   */
  T take() throws InterruptedException;

  /**
   * Returns the next value, waiting at most {@code timeout} for one.
   *
   * @param timeout how long to wait; zero or negative means do not wait
   * @return the next value, or empty if none was published in time
   * @throws InterruptedException if the thread is interrupted while waiting
   * @throws CoreClosedException if the core is closed
   */
  Optional<T> take(Duration timeout) throws InterruptedException;

  /**
   * Returns the next value if one is available now; never blocks.
   *
   * @return the next value, or empty
   * @throws CoreClosedException if the core is closed
   */
  Optional<T> poll();

  /**
   * Returns every value available now, oldest first, possibly none; never blocks.
   *
   * @return a new list
   * @throws CoreClosedException if the core is closed
   */
  List<T> drain();

  /** {@return how many values this reader lost because it fell behind the source's retention} */
  long missed();
}

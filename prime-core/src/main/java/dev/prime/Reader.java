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
 * exactly one of the callers; {@link #poll()} and {@link #drain()} never wait for a value, also
 * while another thread waits in {@link #take()} of the same reader. When the core is closed,
 * blocked and later calls throw {@link CoreClosedException}.
 *
 * <p>A reader is a resource: {@link #close()} it when done, so the source stops keeping values
 * for it (a reader nobody reads falls behind and holds up to the retention of values). After
 * {@code close()}, every call but {@code close()} throws {@link IllegalStateException}.
 *
 * <p>A value the core's codec cannot decode (with {@link CoreConfig.Builder#copyValues} every
 * read decodes a copy of its own; a distributed media decodes every value) is skipped, with a
 * WARN line naming the source and why; the call goes on with the next value.
 *
 * <p>A source that lives outside this process (Optimus: in Redis) may be unreachable for a
 * while. {@link #take()} then waits for it to come back; {@link #take(Duration)} waits at most
 * its timeout (plus about a second for a connection that does not answer) and then throws the
 * media's {@link PrimeException} (Optimus: {@code RedisUnavailableException}) if the source could
 * not be reached, or returns empty if it could and had no value; {@link #poll()} and {@link
 * #drain()} never wait for a reconnect: they throw that exception at once.
 *
 * @param <T> type of the values
 */
public interface Reader<T> extends AutoCloseable {

  /**
   * Returns the next value, waiting until one is published.
   *
   * @return the next value, never {@code null}
   * @throws InterruptedException if the thread is interrupted before or while waiting (within
   *     about a second on a media that waits on the network); a value not yet handed out stays for
   *     the next call. A take that finds a value available does not wait: it returns the value and
   *     leaves the interrupt flag set
   * @throws CoreClosedException if the core is closed
   * @throws IllegalStateException if this reader is closed
   */
  T take() throws InterruptedException;

  /**
   * Returns the next value, waiting at most {@code timeout} for one.
   *
   * @param timeout how long to wait; zero or negative means do not wait: the next value if one is
   *     available now, else empty
   * @return the next value, or empty if none was published in time
   * @throws InterruptedException if the thread is interrupted before or while waiting; as with
   *     {@link #take()}, a value available at once is returned whatever the interrupt flag
   * @throws CoreClosedException if the core is closed
   * @throws IllegalStateException if this reader is closed
   */
  Optional<T> take(Duration timeout) throws InterruptedException;

  /**
   * Returns the next value if one is available now; never waits for one to be published. Where
   * the source is in another process (Optimus: in Redis), it asks there once if this reader holds
   * no value it read before, so it takes a round trip; while that source is unreachable it throws
   * the media's exception ({@code RedisUnavailableException}) within about a second rather than
   * wait for a reconnect, once it has handed out the values this reader had already read.
   *
   * @return the next value, or empty
   * @throws CoreClosedException if the core is closed
   * @throws IllegalStateException if this reader is closed
   */
  Optional<T> poll();

  /**
   * Returns every value available now, oldest first, possibly none; never waits for one to be
   * published. Where the source is in another process, it reads there as {@link #poll()} does;
   * while that source is unreachable it returns the values this reader had already read, if any
   * (the next read then throws if the outage lasts), else throws the media's exception within
   * about a second.
   *
   * @return a new list, which the caller may change (the reader keeps no reference to it)
   * @throws CoreClosedException if the core is closed
   * @throws IllegalStateException if this reader is closed
   */
  List<T> drain();

  /**
   * How many values this reader lost because it fell behind the source's retention. Never waits
   * for a value, also while another thread waits in {@link #take()} of this reader.
   *
   * @return the count since the reader was made
   * @throws CoreClosedException if the core is closed (read the count before closing it)
   * @throws IllegalStateException if this reader is closed
   */
  long missed();

  /**
   * Unregisters this reader: the source keeps no values for it any more, and a call blocked in
   * {@link #take()} ends with {@link IllegalStateException}. Idempotent; never throws, also on a
   * closed core.
   */
  @Override
  void close();
}

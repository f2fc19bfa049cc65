package dev.prime;

import java.util.Objects;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.atomic.AtomicBoolean;
import java.util.function.Consumer;

/**
 * Something that publishes values: a sensor, a timer, an encoder. Logic layer: an event block
 * knows nothing of sources or media; a {@link PrimeCore} turns it into a {@link Source} with
 * {@link PrimeCore#source(EventBlock)}.
 *
 * <p>Thread-safe: {@link #publish} may be called from any thread; subscribers are called on the
 * publishing thread, in subscription order. Publishing with no subscriber does nothing.
 *
 * @param <T> type of the published values
 */
public final class EventBlock<T> {

  /** A subscription to an event block; closing it stops delivery. */
  @FunctionalInterface
  public interface Subscription extends AutoCloseable {
    /** Stops delivering values to this subscriber. Idempotent. */
    @Override
    void close();
  }

  private final CopyOnWriteArrayList<Consumer<? super T>> subscribers = new CopyOnWriteArrayList<>();

  /** Creates an event block with no subscribers. */
  public EventBlock() {}

  /**
   * Publishes one value to every subscriber, on the calling thread. Do not change the value
   * afterwards: readers may see the same object (see {@link CoreConfig.Builder#copyValues}).
   *
   * @param value the value; never {@code null}
   * @throws NullPointerException if {@code value} is {@code null}: sources carry no nulls; publish
   *     an {@link java.util.Optional} or a sentinel value instead
   */
  public void publish(T value) {
    Objects.requireNonNull(
        value, "EventBlock.publish(null): sources carry no nulls; publish an Optional or a sentinel");
    for (Consumer<? super T> subscriber : subscribers) {
      subscriber.accept(value);
    }
  }

  /**
   * Subscribes a consumer; it is called for every value published from now on.
   *
   * @param subscriber called on the publishing thread
   * @return a subscription whose {@code close()} unsubscribes
   */
  public Subscription subscribe(Consumer<? super T> subscriber) {
    Objects.requireNonNull(subscriber, "subscriber must not be null");
    subscribers.add(subscriber);
    // removes one entry once, however often it is closed: the same consumer may be subscribed
    // more than once, and closing one subscription twice must not end another
    AtomicBoolean open = new AtomicBoolean(true);
    return () -> {
      if (open.compareAndSet(true, false)) {
        subscribers.remove(subscriber);
      }
    };
  }
}

package dev.prime;

import java.util.function.Consumer;
import java.util.function.Predicate;

/**
 * A service with one output: an asynchronous stream of values (topology layer).
 *
 * <p>A source is broadcast: every {@link #reader()} sees every value, in publication order,
 * starting at the oldest value the source retains (see {@link CoreConfig#sourceRetention()}).
 * Linking a chain to a source ({@link #then}) starts a service that processes each value and
 * publishes the result to a new source. Services run from {@link PrimeCore#start()} (or at once
 * if the core is already started) until {@link PrimeCore#close()}.
 *
 * <p>Sources never carry {@code null}. Implementations are thread-safe.
 *
 * @param <T> type of the values
 */
public interface Source<T> {

  /** {@return the core that created this source} */
  PrimeCore core();

  /** {@return the source's name, unique within its core} */
  String name();

  /**
   * Creates a reader positioned at the oldest retained value.
   *
   * @return a new reader
   */
  Reader<T> reader();

  /**
   * Runs {@code chain} on every value of this source, as a service, consuming the chain. The
   * chain may take any supertype of the source's values.
   *
   * @param chain the chain to run
   * @param <R> output type
   * @return the source of the chain's outputs
   * @see PrimeCore#link(Source, Chain)
   */
  default <R> Source<R> then(Chain<? super T, R> chain) {
    return core().link(this, chain);
  }

  /**
   * Runs {@code block} on every value of this source, as a service. The block may take any
   * supertype of the source's values and return any subtype of {@code R}.
   *
   * @param block the block to run
   * @param <R> output type
   * @return the source of the block's outputs
   */
  default <R> Source<R> then(Block<? super T, ? extends R> block) {
    return core().link(this, core().chain(Block.<T, R>narrow(block)));
  }

  /**
   * A source of the values of this one that pass {@code predicate}, in order.
   *
   * @param predicate decides which values pass; runs on a service thread
   * @return the filtered source
   */
  default Source<T> filter(Predicate<? super T> predicate) {
    return core().filterSource(this, predicate);
  }

  /**
   * A source of all values that {@code block} makes of each value of this one, in order.
   *
   * @param block turns one value into any number of values (an empty iterable drops it)
   * @param <R> output type
   * @return the flattened source
   */
  default <R> Source<R> flatMap(Block<? super T, ? extends Iterable<? extends R>> block) {
    return core().flatMapSource(this, block);
  }

  /**
   * Calls {@code listener} with every value of this source, on a service thread.
   *
   * @param listener called once per value, in order; an exception goes to the error handler
   */
  default void listen(Consumer<? super T> listener) {
    core().listenSource(this, listener);
  }
}

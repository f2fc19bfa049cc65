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
    return core().linkBlock(this, block);
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
   * <p>Sources never carry {@code null}: a {@code null} element of the iterable is skipped, and
   * a {@code null} iterable drops its value as an empty one does, on every media, without a call
   * of the error handler.
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

  /**
   * A source that pairs each value of this source with the latest value of {@code latest}: the
   * sensor-fusion case (a fast gyro enriched with the latest reading of a slow line sensor).
   * Values of this source published before {@code latest} has any value are dropped (nothing to
   * pair them with); values of {@code latest} only update the latest and emit nothing. A service of
   * this source's core, named {@code withLatestFrom(this|latest)}; its outputs keep this source's
   * order. To emit on the values of both, use {@link PrimeCore#combineLatest(Source, Source)}.
   *
   * @param latest the source whose latest value each value is paired with
   * @param <U> values of {@code latest}
   * @return the source of the pairs: this source's value first
   */
  default <U> Source<Tuple2<T, U>> withLatestFrom(Source<U> latest) {
    return core().combinators().withLatestFrom(this, latest);
  }

  /**
   * A source that publishes, once every {@code period} of the core's clock ({@link
   * CoreConfig#clock()}), the latest value of this source if one arrived since the previous
   * period, and nothing if none did: a fast sensor read at the rate of a slow controller, always
   * its freshest value. Periods count from the core's start (from this call, on a started core,
   * as a timer's do). A service of this source's core, named {@code sample(this)}.
   *
   * @param period how often to publish, positive, at most {@code Long.MAX_VALUE} nanoseconds
   *     (about 292 years)
   * @return the sampled source
   * @throws IllegalArgumentException if the period is not positive or longer than that
   */
  default Source<T> sample(java.time.Duration period) {
    return core().combinators().sample(this, period);
  }

  /**
   * A reader that always returns the newest value, skipping the older ones it has not read (the
   * latest value only: conflation). {@link Reader#take()} waits for a value newer than the last
   * one it returned and returns the newest published by then; {@link Reader#poll()} returns the
   * newest unread value, if any; {@link Reader#drain()} returns at most one value, the newest.
   * Skipped values are not counted in {@link Reader#missed()}, which counts only what the source's
   * retention dropped. Not a service: the conflation happens as the reader reads.
   *
   * @return a new reader, recorded in the topology like {@link #reader()}
   */
  default Reader<T> conflatedReader() {
    return new ConflatedReader<>(reader());
  }
}

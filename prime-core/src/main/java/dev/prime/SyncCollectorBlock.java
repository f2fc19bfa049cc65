package dev.prime;

import java.time.Duration;
import java.util.Deque;
import java.util.Objects;
import java.util.Optional;
import java.util.concurrent.ConcurrentLinkedDeque;
import java.util.function.BooleanSupplier;

/**
 * Returns the next value of a reader on each call, waiting for one if none is there yet.
 *
 * <p>If the calling thread is interrupted while waiting, the interrupt flag is restored and a
 * {@link PrimeException} is thrown. Where the call runs on a service's thread for a caller
 * elsewhere (Optimus), the interrupt reaches only that caller: there the wait also asks the
 * owner whether the caller gave up ({@link PrimeCore#callerGaveUp}), every {@value
 * #CHECK_MILLIS} ms and once when a value comes after a wait, and a yes ends the call with a
 * {@link PrimeException}. A value that came for a caller who gave up is kept for the next call,
 * so the values a caller receives are the source's, in order, with none taken for nobody.
 *
 * <p>Design note: on a media whose callers run the block on their own threads (an in-memory
 * one), a call takes from the reader, with no slices and no checks: the synchronous source row of
 * the benchmarks runs through here. On a media that carries calls between processes, a call
 * first polls (a value ready at once costs no check), then takes in slices of {@value
 * #CHECK_MILLIS} ms. The values kept for the next call are in a concurrent deque, read before
 * the reader: at most one per caller that gave up as a value came.
 *
 * @param <T> value type
 */
final class SyncCollectorBlock<T> implements Block<Token, T> {
  /** How often a call that waits on a service's thread asks whether its caller gave up. */
  private static final long CHECK_MILLIS = 50;

  private static final Duration SLICE = Duration.ofMillis(CHECK_MILLIS);

  private final Reader<T> reader;
  private final BooleanSupplier callerGaveUp; // null: callers run the block on their own threads
  private final Runnable ownerOpen;
  private final Deque<T> keptForTheNextCall = new ConcurrentLinkedDeque<>();

  /**
   * A collector whose callers run it on their own threads.
   *
   * @param reader where the values come from
   */
  SyncCollectorBlock(Reader<T> reader) {
    this(reader, null, () -> {});
  }

  /**
   * A collector that may run on a service's thread for a caller elsewhere.
   *
   * @param reader where the values come from
   * @param callerGaveUp whether the caller of the call the current thread runs gave up
   */
  SyncCollectorBlock(Reader<T> reader, BooleanSupplier callerGaveUp) {
    this(reader, Objects.requireNonNull(callerGaveUp, "callerGaveUp must not be null"), () -> {});
  }

  /**
   * A collector of a core, whose reader that core closes when it closes (one of another core's
   * source): a call that finds the reader closed ends with the owner's check.
   *
   * @param reader where the values come from
   * @param callerGaveUp as above; {@code null} where callers run the block on their own threads
   * @param ownerOpen throws (the core's {@link CoreClosedException}) if the owner closed
   */
  SyncCollectorBlock(Reader<T> reader, BooleanSupplier callerGaveUp, Runnable ownerOpen) {
    this.reader = Objects.requireNonNull(reader, "reader must not be null");
    this.callerGaveUp = callerGaveUp;
    this.ownerOpen = Objects.requireNonNull(ownerOpen, "ownerOpen must not be null");
  }

  @Override
  public T process(Token token) {
    try {
      if (callerGaveUp == null) {
        return reader.take();
      }
      T kept = keptForTheNextCall.pollFirst();
      return kept != null ? kept : takeForACallerElsewhere();
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
      throw new PrimeException("interrupted while a sync collector waited for a value", e);
    } catch (IllegalStateException readerClosed) {
      ownerOpen.run(); // closed with its core: that core's CoreClosedException
      throw readerClosed;
    }
  }

  private T takeForACallerElsewhere() throws InterruptedException {
    Optional<T> ready = reader.poll();
    if (ready.isPresent()) {
      return ready.get();
    }
    while (true) {
      Optional<T> value = reader.take(SLICE);
      boolean gaveUp = callerGaveUp.getAsBoolean();
      if (value.isPresent()) {
        if (!gaveUp) {
          return value.get();
        }
        keptForTheNextCall.addFirst(value.get());
      }
      if (gaveUp) {
        throw new PrimeException(
            "the caller gave up (its timeout passed, or it was interrupted) while a sync collector"
                + " waited for a value"
                + (value.isPresent() ? "; the value that came is kept for the next call" : ""));
      }
    }
  }
}

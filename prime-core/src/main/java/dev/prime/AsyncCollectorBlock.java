package dev.prime;

import java.util.List;
import java.util.Objects;

/**
 * Returns every value a reader received since the previous call (possibly none); never waits.
 *
 * @param <T> value type
 */
final class AsyncCollectorBlock<T> implements Block<Token, List<T>> {
  private final Reader<T> reader;
  private final Runnable ownerOpen;

  /**
   * @param reader where the values come from
   */
  AsyncCollectorBlock(Reader<T> reader) {
    this(reader, () -> {});
  }

  /**
   * A collector of a core, whose reader that core closes when it closes (one of another core's
   * source): a call that finds the reader closed ends with the owner's check.
   *
   * @param reader where the values come from
   * @param ownerOpen throws (the core's {@link CoreClosedException}) if the owner closed
   */
  AsyncCollectorBlock(Reader<T> reader, Runnable ownerOpen) {
    this.reader = Objects.requireNonNull(reader, "reader must not be null");
    this.ownerOpen = Objects.requireNonNull(ownerOpen, "ownerOpen must not be null");
  }

  @Override
  public List<T> process(Token token) {
    try {
      return reader.drain();
    } catch (IllegalStateException readerClosed) {
      ownerOpen.run(); // closed with its core: that core's CoreClosedException
      throw readerClosed;
    }
  }
}

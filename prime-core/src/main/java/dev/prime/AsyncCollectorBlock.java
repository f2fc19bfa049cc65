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

  /**
   * @param reader where the values come from
   */
  AsyncCollectorBlock(Reader<T> reader) {
    this.reader = Objects.requireNonNull(reader, "reader must not be null");
  }

  @Override
  public List<T> process(Token token) {
    return reader.drain();
  }
}

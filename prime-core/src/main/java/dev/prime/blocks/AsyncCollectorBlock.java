package dev.prime.blocks;

import dev.prime.Block;
import dev.prime.Reader;
import dev.prime.Token;
import java.util.List;
import java.util.Objects;

/**
 * Returns every value a reader received since the previous call (possibly none); never waits.
 *
 * @param <T> value type
 */
public final class AsyncCollectorBlock<T> implements Block<Token, List<T>> {
  private final Reader<T> reader;

  /**
   * @param reader where the values come from
   */
  public AsyncCollectorBlock(Reader<T> reader) {
    this.reader = Objects.requireNonNull(reader, "reader must not be null");
  }

  @Override
  public List<T> process(Token token) {
    return reader.drain();
  }
}

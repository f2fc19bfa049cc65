package dev.prime;

import java.util.Objects;

/**
 * Returns the next value of a reader on each call, waiting for one if none is there yet.
 *
 * <p>If the calling thread is interrupted while waiting, the interrupt flag is restored and a
 * {@link PrimeException} is thrown.
 *
 * @param <T> value type
 */
final class SyncCollectorBlock<T> implements Block<Token, T> {
  private final Reader<T> reader;

  /**
   * @param reader where the values come from
   */
  SyncCollectorBlock(Reader<T> reader) {
    this.reader = Objects.requireNonNull(reader, "reader must not be null");
  }

  @Override
  public T process(Token token) {
    try {
      return reader.take();
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
      throw new PrimeException("interrupted while a sync collector waited for a value", e);
    }
  }
}

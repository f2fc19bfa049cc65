package dev.prime;

import java.time.Duration;
import java.util.ArrayList;
import java.util.List;
import java.util.Optional;

/**
 * A reader that returns only the newest value: each read takes what is available and keeps the
 * last of it ({@link Source#conflatedReader()}). A wrapper of a plain reader, so it works on every
 * media; thread-safety is the wrapped reader's.
 *
 * @param <T> value type
 */
final class ConflatedReader<T> implements Reader<T> {
  private final Reader<T> reader;

  ConflatedReader(Reader<T> reader) {
    this.reader = reader;
  }

  @Override
  public T take() throws InterruptedException {
    return newest(reader.take());
  }

  @Override
  public Optional<T> take(Duration timeout) throws InterruptedException {
    return reader.take(timeout).map(this::newest);
  }

  @Override
  public Optional<T> poll() {
    List<T> available = reader.drain();
    return available.isEmpty()
        ? Optional.empty()
        : Optional.of(available.get(available.size() - 1));
  }

  @Override
  public List<T> drain() {
    List<T> newest = new ArrayList<>(1); // a new list the caller may change, as Reader promises
    poll().ifPresent(newest::add);
    return newest;
  }

  @Override
  public long missed() {
    return reader.missed();
  }

  @Override
  public void close() {
    reader.close();
  }

  /**
   * {@code first}, or the newest value published after it, if any is available now. A drain that
   * fails (on a media whose sources live elsewhere: the source became unreachable, or answered too
   * slowly, as the drain looked for more) returns {@code first}: the wrapped reader handed it out
   * already, so throwing would lose it. The failure comes again at the next read if it lasts.
   */
  private T newest(T first) {
    List<T> later;
    try {
      later = reader.drain();
    } catch (RuntimeException e) {
      return first;
    }
    return later.isEmpty() ? first : later.get(later.size() - 1);
  }

  @Override
  public String toString() {
    return "ConflatedReader[" + reader + "]";
  }
}

package dev.prime.test.internal;

import java.util.concurrent.atomic.AtomicBoolean;
import org.junit.jupiter.api.extension.ExtensionContext;

/**
 * The Redis of one test class's Optimus runs: kept in the class's extension store, so JUnit closes
 * it (stopping an embedded server) when the class is done. It is a {@link
 * ExtensionContext.Store.CloseableResource} as well as an {@link AutoCloseable}: JUnit closes the
 * latter only from 5.13 on (and not when {@code
 * junit.jupiter.extensions.store.close.autocloseable.enabled} is false), the former on every
 * JUnit 5; one that is both is closed once.
 */
@SuppressWarnings("deprecation") // CloseableResource: how JUnit before 5.13 closes a store's value
final class SharedRedis implements AutoCloseable, ExtensionContext.Store.CloseableResource {
  private final String url;
  private final Runnable stop;
  private final AtomicBoolean closed = new AtomicBoolean();

  /**
   * @param url where the Redis answers
   * @param stop stops the embedded server, or {@code null} for a Redis not ours
   */
  SharedRedis(String url, Runnable stop) {
    this.url = url;
    this.stop = stop;
  }

  String url() {
    return url;
  }

  /** Stops the embedded server, if it is ours; only the first call does anything. */
  @Override
  public void close() {
    if (closed.compareAndSet(false, true) && stop != null) {
      stop.run();
    }
  }
}

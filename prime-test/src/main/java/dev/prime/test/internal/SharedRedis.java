package dev.prime.test.internal;

/**
 * The Redis of one test class's Optimus runs: kept in the class's extension store, so JUnit closes
 * it (stopping an embedded server) when the class is done.
 */
final class SharedRedis implements AutoCloseable {
  private final String url;
  private final Runnable stop;

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

  @Override
  public void close() {
    if (stop != null) {
      stop.run();
    }
  }
}

package dev.prime.inspector.internal;

/**
 * The latest figures, posted by the sampler and awaited by every open event stream: one writer,
 * many readers, each waiting for a generation newer than the one it sent. A monitor is enough
 * (two posts a second); {@link #close()} wakes every waiter for good.
 */
final class FigureBoard {
  /** One posting: the figures as JSON and its generation (1, 2, ...). */
  record Posting(long generation, String json) {}

  private Posting latest; // guarded by this
  private boolean closed; // guarded by this

  synchronized void post(String json) {
    latest = new Posting(latest == null ? 1 : latest.generation() + 1, json);
    notifyAll();
  }

  /**
   * Waits for a posting newer than {@code seen}.
   *
   * @return it, or {@code null} if none came within the timeout or the board is closed
   */
  synchronized Posting awaitAfter(long seen, long timeoutMillis) throws InterruptedException {
    long deadline = System.nanoTime() + timeoutMillis * 1_000_000;
    while (!closed && (latest == null || latest.generation() <= seen)) {
      long left = (deadline - System.nanoTime()) / 1_000_000;
      if (left <= 0) {
        return null;
      }
      wait(left);
    }
    return closed ? null : latest;
  }

  synchronized boolean isClosed() {
    return closed;
  }

  synchronized void close() {
    closed = true;
    notifyAll();
  }
}

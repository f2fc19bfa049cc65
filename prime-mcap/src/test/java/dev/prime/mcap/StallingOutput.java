package dev.prime.mcap;

import java.io.IOException;
import java.nio.ByteBuffer;
import java.nio.file.Path;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;

/**
 * A file output that a test can stall: once {@link #stall()} is called, the next write blocks
 * (and says so through {@link #awaitBlocked}) until {@link #release()}; or it can be made to
 * fail. A disk that cannot keep up, without sleeps.
 */
final class StallingOutput extends ForwardingFileChannel {
  private volatile boolean stalled;
  private volatile boolean failing;
  private volatile RuntimeException bug;
  private final CountDownLatch blocked = new CountDownLatch(1);
  private final CountDownLatch released = new CountDownLatch(1);

  StallingOutput(Path path) throws IOException {
    super(OutputOpener.FILES.open(path));
  }

  /** The next writes block until {@link #release()}. */
  void stall() {
    stalled = true;
  }

  /** The next writes throw, as a full or failed disk would. */
  void fail() {
    failing = true;
  }

  /** The next writes throw this unchecked exception, as a bug below the writer would. */
  void failWith(RuntimeException exception) {
    bug = exception;
  }

  void release() {
    released.countDown();
  }

  boolean awaitBlocked(long seconds) throws InterruptedException {
    return blocked.await(seconds, TimeUnit.SECONDS);
  }

  private void gate() throws IOException {
    if (bug != null) {
      throw bug;
    }
    if (failing) {
      throw new IOException("No space left on device (simulated)");
    }
    if (stalled) {
      blocked.countDown();
      try {
        if (!released.await(60, TimeUnit.SECONDS)) {
          throw new IOException("the test never released the stalled output");
        }
      } catch (InterruptedException e) {
        Thread.currentThread().interrupt();
        throw new IOException("interrupted while stalled", e);
      }
    }
  }

  @Override
  public int write(ByteBuffer source) throws IOException {
    gate();
    return super.write(source);
  }

  @Override
  public long write(ByteBuffer[] sources, int offset, int length) throws IOException {
    gate();
    return super.write(sources, offset, length);
  }

  @Override
  public int write(ByteBuffer source, long position) throws IOException {
    gate();
    return super.write(source, position);
  }
}

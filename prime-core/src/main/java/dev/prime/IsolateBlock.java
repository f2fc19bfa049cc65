package dev.prime;

import java.util.Objects;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.locks.ReentrantLock;

/**
 * Lets several callers share one block without ever running it concurrently: calls are
 * serialised by a fair lock, so no caller starves.
 *
 * <p>A caller waiting for its turn honours interruption: it stops waiting, keeps its interrupt
 * flag set and gets a {@link PrimeException}; the block is not run for it. A waiting caller also
 * runs a check given by the owner every {@value #CHECK_MILLIS} ms (a core passes its open check,
 * so closing the core ends the wait with {@link dev.prime.CoreClosedException}).
 *
 * @param <I> input type
 * @param <O> output type
 */
final class IsolateBlock<I, O> implements Block<I, O> {
  private final Block<I, O> block;
  /** How often a waiting caller runs the owner's check. */
  private static final long CHECK_MILLIS = 50;

  private final ReentrantLock lock = new ReentrantLock(true);
  private final Runnable whileWaiting;

  /**
   * A shared block whose waiting callers stop only when interrupted.
   *
   * @param block the shared block
   */
  IsolateBlock(Block<I, O> block) {
    this(block, () -> {});
  }

  /**
   * @param block the shared block
   * @param whileWaiting runs repeatedly while a caller waits for its turn; throws to end the wait
   *     (the block is then not run for that caller)
   */
  IsolateBlock(Block<I, O> block, Runnable whileWaiting) {
    this.block = Objects.requireNonNull(block, "isolated block must not be null");
    this.whileWaiting = Objects.requireNonNull(whileWaiting, "whileWaiting must not be null");
  }

  @Override
  public O process(I input) {
    try {
      while (!lock.tryLock(CHECK_MILLIS, TimeUnit.MILLISECONDS)) {
        whileWaiting.run();
      }
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
      throw new PrimeException("interrupted while waiting for the isolated chain to be free", e);
    }
    try {
      return block.process(input);
    } finally {
      lock.unlock();
    }
  }
}

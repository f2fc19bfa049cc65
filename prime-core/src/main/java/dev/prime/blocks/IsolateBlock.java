package dev.prime.blocks;

import dev.prime.Block;
import dev.prime.PrimeException;
import java.util.Objects;
import java.util.concurrent.locks.ReentrantLock;

/**
 * Lets several callers share one block without ever running it concurrently: calls are
 * serialised by a fair lock, so no caller starves.
 *
 * <p>A caller waiting for its turn honours interruption: it stops waiting, keeps its interrupt
 * flag set and gets a {@link PrimeException}; the block is not run for it.
 *
 * @param <I> input type
 * @param <O> output type
 */
public final class IsolateBlock<I, O> implements Block<I, O> {
  private final Block<I, O> block;
  private final ReentrantLock lock = new ReentrantLock(true);

  /**
   * @param block the shared block
   */
  public IsolateBlock(Block<I, O> block) {
    this.block = Objects.requireNonNull(block, "isolated block must not be null");
  }

  @Override
  public O process(I input) {
    try {
      lock.lockInterruptibly();
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
